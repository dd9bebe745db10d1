#include <dvs_line_tracker/overload_governor.h>

#include <algorithm>
#include <cmath>

namespace dvs_line_tracker
{
namespace
{
// The cost is the time over the events of about the latest kCostHorizonEvents tracked events
// (each packet weighted by its events): a packet of a few events delayed by the scheduler
// (0.4 ms for 10 events, 44 us each, where 0.4 us is usual) moved a per-packet running mean
// tenfold, and the stride to 40 for the next packets (a lost track in tracker_overload.test).
constexpr double kCostHorizonEvents = 5000;
}

int OverloadGovernor::strideFor(size_t queued_events, bool initialising)
{
  int stride = 1;
  const double cost = (initialising ? initialising_ : tracking_).perEvent();
  if (params_.max_latency_s > 0 && cost > 0)
  {
    // Tracking every k-th of the queued events takes queued * cost / k.
    const double needed = std::ceil(static_cast<double>(queued_events) * cost / params_.max_latency_s);
    stride = static_cast<int>(std::min<double>(std::max(needed, 1.0), params_.max_stride));
  }
  stats_.last_stride = stride;
  stats_.max_stride_used = std::max(stats_.max_stride_used, stride);
  if (stride > 1 && !initialising)
    ++stats_.packets_strided;
  return stride;
}

bool OverloadGovernor::skipWholePacket(int stride, size_t events)
{
  if (stride <= 1 || packet_phase_++ % static_cast<uint64_t>(stride) == 0)
    return false;
  ++stats_.packets_skipped;
  stats_.events_skipped_whole += events;
  skipped(events);
  return true;
}

void OverloadGovernor::tracked(size_t tracked, double seconds, bool initialising)
{
  if (tracked == 0 || !(seconds >= 0))
    return;
  Cost& c = initialising ? initialising_ : tracking_;
  const double keep = kCostHorizonEvents / (kCostHorizonEvents + static_cast<double>(tracked));
  c.seconds = keep * c.seconds + seconds;
  c.events = keep * c.events + static_cast<double>(tracked);
}
}  // namespace dvs_line_tracker
