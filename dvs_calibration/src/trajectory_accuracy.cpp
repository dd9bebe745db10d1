#include <dvs_calibration/trajectory_accuracy.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dvs_calibration
{
AccuracyReport evaluateTrajectory(const Trajectory& estimates, const Trajectory& ground_truth,
                                  const AccuracyOptions& o)
{
  AccuracyReport r;
  if (estimates.empty())
    return r;
  r.first_estimate_s = estimates.front().t;
  double sp = 0, so = 0;
  size_t j = 0;
  for (const auto& gt : ground_truth)
  {
    if (gt.t < estimates.front().t || gt.t < o.from_s || gt.t > o.to_s)
      continue;
    while (j + 1 < estimates.size() && estimates[j + 1].t <= gt.t)
      ++j;
    ++r.samples;
    if (gt.t - estimates[j].t > o.max_age_s)
      continue;
    ++r.samples_fresh;
    const double ep = positionError(estimates[j].T_world_camera, gt.T_world_camera);
    const double eo = orientationError(estimates[j].T_world_camera, gt.T_world_camera);
    if (ep <= o.max_position_m && eo <= o.max_orientation_rad)
      ++r.samples_tracked;
    sp += ep * ep;
    so += eo * eo;
    r.mean_position_m += ep;
    r.mean_orientation_rad += eo;
    r.max_position_m = std::max(r.max_position_m, ep);
    r.max_orientation_rad = std::max(r.max_orientation_rad, eo);
  }
  if (r.samples_fresh > 0)
  {
    r.rms_position_m = std::sqrt(sp / r.samples_fresh);
    r.rms_orientation_rad = std::sqrt(so / r.samples_fresh);
    r.mean_position_m /= r.samples_fresh;
    r.mean_orientation_rad /= r.samples_fresh;
  }
  return r;
}

AccuracyReport evaluateTrajectory(const Trajectory& estimates, const Trajectory& ground_truth, double max_age_s,
                                  double from_s, double to_s)
{
  AccuracyOptions o;
  o.max_age_s = max_age_s;
  o.from_s = from_s;
  o.to_s = to_s;
  return evaluateTrajectory(estimates, ground_truth, o);
}

std::string AccuracyReport::json() const
{
  const double deg = 180.0 / M_PI;
  char buf[640];
  std::snprintf(buf, sizeof(buf),
                "{\"samples\": %d, \"samples_fresh\": %d, \"samples_tracked\": %d, \"tracked_fraction\": %.6f, "
                "\"rms_position_m\": %.6f, \"rms_orientation_deg\": %.6f, \"max_position_m\": %.6f, "
                "\"max_orientation_deg\": %.6f, \"mean_position_m\": %.6f, \"mean_orientation_deg\": %.6f, "
                "\"first_estimate_s\": %.6f}",
                samples, samples_fresh, samples_tracked, trackedFraction(), rms_position_m, rms_orientation_rad * deg,
                max_position_m, max_orientation_rad * deg, mean_position_m, mean_orientation_rad * deg,
                first_estimate_s);
  return buf;
}
}  // namespace dvs_calibration
