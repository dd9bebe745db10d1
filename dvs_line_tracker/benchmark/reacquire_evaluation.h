#pragma once
// Re-acquisition after a loss (issue 14, part 2): a sweep scene (sweep_scene.h) with one seeded
// disturbance while the tracker is tracking, and how soon after it a correct pose is back.
// The disturbances are the issue's:
//  - blackout: no events at all for 0.2-1 s (a cable, a driver stall, the bias being reset);
//  - occlusion: for 0.2-1 s, no events on one side of a line through the map's centre (a hand,
//    a branch across half the target);
//  - bump: the camera knocked by 8-20 deg about a random axis within 20 ms, and staying there;
//  - leaving the view: the camera turned away until the whole map is outside the image for
//    0.2-1 s, then back (0.15 s each way).
#include "sweep_evaluation.h"

#include <dvs_calibration/pose.h>
#include <dvs_screen_sim/trajectory.h>

#include <memory>

namespace dvs_line_tracker
{
enum class DisturbanceKind
{
  kBlackout,
  kOcclusion,
  kBump,
  kLeaveView,
};

const char* disturbanceLabel(DisturbanceKind kind);

struct Disturbance
{
  DisturbanceKind kind = DisturbanceKind::kBlackout;
  double start_s = 0;   ///< when it begins
  double length_s = 0;  ///< blackout / occlusion / out of view: how long
  double angle_deg = 0; ///< bump: the knock; leaving the view: how far the camera turns
  Eigen::Vector3d axis_camera = Eigen::Vector3d::UnitY();  ///< bump / leaving: the turn's axis (camera frame)
  Eigen::Vector2d occluder_point = Eigen::Vector2d::Zero();   ///< occlusion: events with
  Eigen::Vector2d occluder_normal = Eigen::Vector2d::UnitX(); ///< normal . (px - point) > 0 are hidden
  /// When the map is fully back (the events return, the knock is over, the camera has turned back).
  double backAt() const;
};

/// The rotation of the camera (about its own centre, camera frame) the disturbance adds at `t`.
Eigen::Matrix3d disturbanceRotation(const Disturbance& d, double t);

/// A scene trajectory with a disturbance's turn added (bump, leaving the view; the others leave
/// it unchanged).
class DisturbedTrajectory : public dvs_screen_sim::Trajectory
{
public:
  DisturbedTrajectory(std::shared_ptr<const dvs_screen_sim::Trajectory> base, const Disturbance& d)
    : base_(std::move(base)), d_(d)
  {
  }
  dvs_calibration::Pose poseAt(double t) const override;
  double naturalDuration() const override { return base_->naturalDuration(); }

private:
  std::shared_ptr<const dvs_screen_sim::Trajectory> base_;
  Disturbance d_;
};

/// Sweep scene `spec` as the re-acquisition runs it: a flip repeats every 1.2 s (after a
/// disturbance, a camera hovering nearly still would show the map too little to find it).
SweepScene buildReacquireScene(SweepSceneSpec spec);

/// The disturbance of sweep scene `scene` (kind by `index`, the rest from the scene's seed): it
/// starts `lead_s` after the map's edges fire (`edges_fire_s`).
Disturbance sweepDisturbance(const SweepScene& scene, int index, double edges_fire_s, double lead_s = 0.4);

struct ReacquireResult
{
  Disturbance disturbance;
  double edges_fire_s = -1;
  /// At the disturbance's start: tracking, with a pose within 10 % of the distance and 10 deg.
  bool tracking_before = false;
  /// When, after backAt(), at least three map edges (or all) have swept a pixel in view within
  /// 0.2 s (-1: not within 1.5 s): the motion the map needs to be seen again.
  double edges_refire_s = -1;
  /// First pose within 5 % / 3 deg of the truth at or after edges_refire_s (-1: none), minus
  /// edges_refire_s.
  double back_after_s = -1;
  bool kept = false;                ///< the track was never lost (no re-initialisation)
  int reinitializations = 0;        ///< after the disturbance's start
  int false_reinitializations = 0;  ///< of those, further than 10 % / 10 deg from the truth
  /// Ground-truth samples from edges_refire_s + 0.3 s on with >= 3 edges in view, tracked (10 % / 10 deg).
  double tracked_after = 0;
  double rms_after_ratio = 0;  ///< RMS position error over the same span / the start distance
  double tracker_cpu_s = 0;
  std::string last_loss_reason;
  InitializerStats init_stats;
};

/// The scene with its disturbance: the trajectory turned (bump, leaving the view), simulated
/// until 0.8 s after the map's edges fire again (at most 1.5 s after backAt() + 0.8 s), the
/// events the blackout or occlusion hides removed. `edges_refire_s` receives the firing time.
struct DisturbedScene
{
  SweepScene scene;
  Disturbance disturbance;
  double edges_fire_s = -1, edges_refire_s = -1;
  dvs_driver::EventVector events;
};
DisturbedScene disturbSweepScene(const SweepScene& scene, int index);

/// Runs a fresh tracker with `params` over the disturbed scene `index` of the sweep.
ReacquireResult runReacquireScene(const SweepScene& scene, int index, const LineTrackerParams& params = LineTrackerParams());
}  // namespace dvs_line_tracker
