#pragma once
// Accuracy of an estimated trajectory against ground truth, as the issue and thesis measure it:
// at every ground-truth sample from the first estimate on, the latest estimate at or before
// that time is compared (position error = distance of the camera centres, orientation error =
// angle of R_est^T R_gt).
#include <dvs_line_tracker/camera_pose.h>

#include <vector>

namespace dvs_line_tracker
{
struct StampedPose
{
  double t_s;
  CameraPose pose;
};

struct AccuracyReport
{
  int samples = 0;            ///< ground-truth samples from the first estimate on
  int samples_tracked = 0;    ///< of those, with an estimate younger than max_age_s
  double rms_position_m = 0, rms_orientation_rad = 0;
  double max_position_m = 0, max_orientation_rad = 0;
  double mean_position_m = 0, mean_orientation_rad = 0;
  double first_estimate_s = -1;
};

/// `estimates` sorted by time. Samples whose latest estimate is older than `max_age_s` count as
/// not tracked and are left out of the error statistics.
AccuracyReport evaluateTrajectory(const std::vector<StampedPose>& estimates,
                                  const std::vector<StampedPose>& ground_truth, double max_age_s = 0.05,
                                  double from_s = -1e300, double to_s = 1e300);
}  // namespace dvs_line_tracker
