#include <dvs_line_tracker/overload_governor.h>

#include <algorithm>
#include <cmath>

namespace dvs_line_tracker
{
namespace
{
constexpr double kCostAlpha = 0.2;  // running mean of the cost over ~5 packets
}

int OverloadGovernor::strideFor(size_t queued_events, bool whole_packets)
{
  int stride = 1;
  if (params_.max_latency_s > 0 && seconds_per_event_ > 0)
  {
    // Tracking every k-th of the queued events takes queued * cost / k.
    const double needed = std::ceil(static_cast<double>(queued_events) * seconds_per_event_ / params_.max_latency_s);
    stride = static_cast<int>(std::min<double>(std::max(needed, 1.0), params_.max_stride));
  }
  stats_.last_stride = stride;
  stats_.max_stride_used = std::max(stats_.max_stride_used, stride);
  if (stride > 1 && !whole_packets)
    ++stats_.packets_strided;
  return stride;
}

bool OverloadGovernor::skipWholePacket(int stride, size_t events)
{
  if (stride <= 1 || packet_phase_++ % static_cast<uint64_t>(stride) == 0)
    return false;
  ++stats_.packets_skipped;
  skipped(events);
  return true;
}

void OverloadGovernor::tracked(size_t tracked, double seconds)
{
  if (tracked == 0 || !(seconds >= 0))
    return;
  const double cost = seconds / static_cast<double>(tracked);
  seconds_per_event_ = seconds_per_event_ > 0 ? seconds_per_event_ + kCostAlpha * (cost - seconds_per_event_) : cost;
}
}  // namespace dvs_line_tracker
