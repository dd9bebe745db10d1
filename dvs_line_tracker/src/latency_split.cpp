#include <dvs_line_tracker/latency_split.h>

#include <cmath>

namespace dvs_line_tracker
{
void LatencySplit::beginPacket(const PacketTiming& p)
{
  last_event_ns_ = p.last_event_ns;
  const double transport = 1e-9 * double(p.arrival_clock_ns - p.last_event_ns);
  clock_ok_ = std::abs(transport) <= kMaxClockOffsetS;
  if (clock_ok_)
    transport_.add(transport, p.events);
  else
    ++clock_mismatches_;
  queue_.add(p.queue_s, p.events);
  processing_.add(p.processing_s, p.events);
  publishing_.add(p.publishing_s, p.events);
  after_last_event_s_ = transport + p.queue_s + p.processing_s + p.publishing_s;
}

void LatencySplit::reset()
{
  for (LatencyHistogram* h : {&total_, &accumulation_, &transport_, &queue_, &processing_, &publishing_})
    h->reset();
  clock_mismatches_ = 0;
}
}  // namespace dvs_line_tracker
