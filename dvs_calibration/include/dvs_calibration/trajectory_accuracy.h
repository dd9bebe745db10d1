#pragma once
// The suite's one trajectory-accuracy metric, used by the tools, the tests, the benchmarks and
// the demo's report (through the evaluate_trajectory tool): at every ground-truth sample from
// the first estimate on (within [from, to]), the estimate in force is the latest one at or
// before that time (what a controller would have had). Position error = distance of the camera
// centres, orientation error = angle of R_est^T R_gt. A sample is tracked when its estimate is
// at most `max_age_s` old and its errors are within `max_position_m` / `max_orientation_rad`;
// the RMS, mean and max are over the samples whose estimate is fresh.
#include <dvs_calibration/pose.h>

#include <string>

namespace dvs_calibration
{
struct AccuracyOptions
{
  double max_age_s = 0.05;              ///< an older estimate counts as no estimate
  double max_position_m = 0.10;         ///< tracked: position error within this
  double max_orientation_rad = 10.0 * M_PI / 180.0;  ///< and orientation error within this
  double from_s = -1e300, to_s = 1e300; ///< ground-truth samples outside are ignored
};

struct AccuracyReport
{
  int samples = 0;          ///< ground-truth samples from the first estimate on
  int samples_fresh = 0;    ///< of those, with an estimate at most max_age_s old
  int samples_tracked = 0;  ///< of those, within the error bounds
  double rms_position_m = 0, rms_orientation_rad = 0;
  double max_position_m = 0, max_orientation_rad = 0;
  double mean_position_m = 0, mean_orientation_rad = 0;
  double first_estimate_s = -1;  ///< time of the first estimate (-1: none)

  double trackedFraction() const { return samples > 0 ? static_cast<double>(samples_tracked) / samples : 0.0; }
  /// One JSON object (keys as the fields, plus tracked_fraction; metres and degrees).
  std::string json() const;
};

/// `estimates` and `ground_truth` sorted by time (non-decreasing).
AccuracyReport evaluateTrajectory(const Trajectory& estimates, const Trajectory& ground_truth,
                                  const AccuracyOptions& options = AccuracyOptions());
/// The same with the default error bounds and the given age limit and time range.
AccuracyReport evaluateTrajectory(const Trajectory& estimates, const Trajectory& ground_truth, double max_age_s,
                                  double from_s = -1e300, double to_s = 1e300);
}  // namespace dvs_calibration
