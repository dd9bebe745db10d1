#include <dvs_line_tracker/trajectory_evaluation.h>

#include <algorithm>
#include <cmath>

namespace dvs_line_tracker
{
AccuracyReport evaluateTrajectory(const std::vector<StampedPose>& estimates,
                                  const std::vector<StampedPose>& ground_truth, double max_age_s, double from_s,
                                  double to_s)
{
  AccuracyReport r;
  if (estimates.empty())
    return r;
  r.first_estimate_s = estimates.front().t_s;
  double sp = 0, so = 0;
  size_t j = 0;
  for (const auto& gt : ground_truth)
  {
    if (gt.t_s < estimates.front().t_s || gt.t_s < from_s || gt.t_s > to_s)
      continue;
    while (j + 1 < estimates.size() && estimates[j + 1].t_s <= gt.t_s)
      ++j;
    ++r.samples;
    if (gt.t_s - estimates[j].t_s > max_age_s)
      continue;
    ++r.samples_tracked;
    const double ep = positionError(estimates[j].pose, gt.pose);
    const double eo = orientationError(estimates[j].pose, gt.pose);
    sp += ep * ep;
    so += eo * eo;
    r.mean_position_m += ep;
    r.mean_orientation_rad += eo;
    r.max_position_m = std::max(r.max_position_m, ep);
    r.max_orientation_rad = std::max(r.max_orientation_rad, eo);
  }
  if (r.samples_tracked > 0)
  {
    r.rms_position_m = std::sqrt(sp / r.samples_tracked);
    r.rms_orientation_rad = std::sqrt(so / r.samples_tracked);
    r.mean_position_m /= r.samples_tracked;
    r.mean_orientation_rad /= r.samples_tracked;
  }
  return r;
}
}  // namespace dvs_line_tracker
