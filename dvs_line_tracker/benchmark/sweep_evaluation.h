#pragma once
// Simulating a sweep scene and measuring the tracker on it against ground truth: when the map's
// edges start firing, when and how well the tracker gives its first pose, false
// initialisations, the tracked fraction while at least three map edges are in view, and the RMS.
#include "covariance_consistency.h"
#include "sweep_scene.h"

#include <dvs_calibration/trajectory_accuracy.h>

#include <dvs_line_tracker/tracker_initializer.h>
#include <dvs_line_tracker/tracker_params.h>

#include <dvs_driver/event.h>

#include <cstdint>
#include <string>

namespace dvs_line_tracker
{
struct SweepResult
{
  uint64_t events = 0;
  /// Ground truth: the first time at least three map edges (or all, if fewer) are in view and
  /// have each swept one pixel since the start, i.e. have drawn themselves in events.
  double edges_fire_s = -1;
  double first_pose_s = -1;        ///< event time of the first pose (-1: none)
  double first_pose_delay_s = -1;  ///< first_pose_s - edges_fire_s (-1: none)
  bool first_pose_correct = false; ///< within 5 % of the distance and 3 deg
  int initializations = 0;         ///< first poses and re-initialisations
  int false_initializations = 0;   ///< of those, further than 10 % of the distance or 10 deg from the truth
  int losses = 0;
  /// Partial views held (a corner only in view, partial_view_grace_s), those resumed, and the
  /// event time held (TrackerStats).
  uint64_t partial_views_held = 0, partial_views_resumed = 0;
  double partial_view_held_s = 0;
  double tracked_fraction = 0;     ///< ground-truth samples from the first pose on with >= 3 edges in view
  double rms_position_m = 0, rms_orientation_deg = 0;
  double max_position_m = 0;
  double rms_position_ratio = 0;   ///< rms_position_m / the start distance
  double tracker_cpu_s = 0, simulator_cpu_s = 0;
  uint64_t events_outside_sensor = 0;
  InitializerStats init_stats;
  std::string last_loss_reason;
  /// Every 1 ms of event time while tracking: the pose's error against the vision-only
  /// covariance the odometry reports (LineTracker::visionOnlyPoseCovariance), and against its
  /// Gauss-Newton part alone (visionPoseCovariance x kVisionOnlyCovarianceScale, without the lag).
  CovarianceConsistency consistency, consistency_without_lag;
};

/// Whether any part of the map projects into the (distorted) image at `pose` (sampled along its
/// edges).
bool mapInView(const SweepScene& scene, const dvs_calibration::Pose& pose);

/// `estimate` within `distance_ratio` of the camera's distance to the map centre and `angle_deg`
/// of `truth` (the sweep's bounds: 5 % / 3 deg correct, beyond 10 % / 10 deg false).
bool poseWithin(const SweepScene& scene, const dvs_calibration::Pose& truth, const dvs_calibration::Pose& estimate,
                double distance_ratio, double angle_deg);

/// What counts as tracked against the scene's ground truth: a pose at most 50 ms old, within
/// 10 % of the start distance and 10 deg.
dvs_calibration::AccuracyOptions sweepAccuracyOptions(const SweepScene& scene);

/// Map edges at least 10 px long in the (distorted) image at `pose`.
int visibleEdges(const SweepScene& scene, const dvs_calibration::Pose& pose);

/// The first ground-truth time at which at least min(3, segments) visible map edges have each
/// swept one pixel while in view since `from_s` (-1: never); with `window_s` > 0, one pixel
/// within the last `window_s`.
double edgesFireTime(const SweepScene& scene, const dvs_calibration::Trajectory& ground_truth, double from_s = -1e300,
                     double window_s = 0);

/// The scene's events from the software DVS (seeded by spec.seed); `cpu_s` (optional) receives
/// the simulation's thread CPU time.
dvs_driver::EventVector simulateSweepScene(const SweepScene& scene, double* cpu_s = nullptr);

/// Write `events` of `scene` and its ground truth into the existing folder `dir`: events.txt,
/// groundtruth.txt (TUM, 1 kHz), calib.txt, size.txt, map.yaml (throws on a write error).
void writeSweepSceneFiles(const std::string& dir, const SweepScene& scene, const dvs_driver::EventVector& events);

/// Simulates the scene (seeded by spec.seed) and runs a fresh tracker with `params` over it.
SweepResult runSweepScene(const SweepScene& scene, const LineTrackerParams& params = LineTrackerParams());
}  // namespace dvs_line_tracker
