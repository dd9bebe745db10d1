#include <dvs_screen_sim/screen_loop/live_event_collector.h>

namespace dvs_screen_sim
{
namespace screen_loop
{
void LiveEventCollector::addPacket(const dvs_driver::Event* begin, const dvs_driver::Event* end,
                                   int64_t arrival_host_ns)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (begin != end)
    clock_.addPacket((end - 1)->t_ns, arrival_host_ns);
  if (!keeping_)
    return;
  kept_.insert(kept_.end(), begin, end);
}

int64_t LiveEventCollector::dvsTimeNs(int64_t host_ns) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return clock_.toDvsNs(host_ns);
}

bool LiveEventCollector::clockValid() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return clock_.valid();
}

size_t LiveEventCollector::packets() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return clock_.packets();
}

void LiveEventCollector::keepFrom(int64_t)
{
  std::lock_guard<std::mutex> lock(mutex_);
  keeping_ = true;
  kept_.clear();
}

dvs_driver::EventVector LiveEventCollector::takeKept()
{
  std::lock_guard<std::mutex> lock(mutex_);
  keeping_ = false;
  dvs_driver::EventVector out;
  out.swap(kept_);
  return out;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
