#include <dvs_line_tracker/overload_governor.h>

#include <algorithm>
#include <cmath>

namespace dvs_line_tracker
{
namespace
{
constexpr double kCostAlpha = 0.2;   // running mean of the cost over ~5 packets
constexpr double kBackToFull = 0.25; // the batched solve ends when the queue takes less than this x the budget
}

OverloadAction OverloadGovernor::actionFor(size_t queued_events)
{
  OverloadAction a;
  if (params_.max_latency_s > 0 && seconds_per_event_ > 0)
  {
    // The time the queue takes at the current mode's cost, in budgets.
    const double load = static_cast<double>(queued_events) * seconds_per_event_ / params_.max_latency_s;
    if (!batched_ && load > 1.0 && params_.batch_solve_every > 1)
      batched_ = true;  // the cheaper solve first; its cost is measured from the next packet on
    else if (batched_ && load < kBackToFull)
      batched_ = false;
    else if (batched_ || params_.batch_solve_every <= 1)
      // Tracking every k-th of the queued events takes load / k budgets.
      a.stride = static_cast<int>(std::min<double>(std::max(std::ceil(load), 1.0), params_.max_stride));
    if (batched_)
      a.solve_every = params_.batch_solve_every;
  }
  stats_.last = a;
  stats_.max_stride_used = std::max(stats_.max_stride_used, a.stride);
  stats_.packets_batched += a.solve_every > 1 ? 1 : 0;
  stats_.packets_strided += a.stride > 1 ? 1 : 0;
  return a;
}

void OverloadGovernor::tracked(size_t tracked, double seconds)
{
  if (tracked == 0 || !(seconds >= 0))
    return;
  const double cost = seconds / static_cast<double>(tracked);
  seconds_per_event_ = seconds_per_event_ > 0 ? seconds_per_event_ + kCostAlpha * (cost - seconds_per_event_) : cost;
}
}  // namespace dvs_line_tracker
