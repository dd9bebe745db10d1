#include "reacquire_evaluation.h"

#include "benchmark_stats.h"

#include <dvs_line_tracker/line_tracker.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace dvs_line_tracker
{
namespace
{
constexpr double kDeg = M_PI / 180.0;
constexpr double kBumpRampS = 0.02;   ///< the knock's duration
constexpr double kTurnRampS = 0.15;   ///< turning away from the map, and back
constexpr double kTailS = 0.8;        ///< simulated after the map's edges fire again
constexpr double kMaxWaitS = 1.5;     ///< for them to fire again after the disturbance
/// They fire again when they sweep a pixel within this long: a camera that hovers nearly still
/// after a disturbance draws too few events on the map to see it among the noise (a DVS128
/// hovering after a flip with 2 Hz/px background, 5 px/s: no edge in 0.1 s of events).
constexpr double kRefireWindowS = 0.2;
constexpr double kFlipRepeatS = 1.2;
constexpr double kSettleS = 0.3;      ///< the issue's re-acquisition time: tracked fraction counted after it

/// 0 before 0, 1 after 1, smooth (zero slope at both ends) between.
double smoothStep(double x)
{
  x = std::min(1.0, std::max(0.0, x));
  return x * x * (3 - 2 * x);
}

double uniform(std::mt19937_64& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
}  // namespace

const char* disturbanceLabel(DisturbanceKind kind)
{
  switch (kind)
  {
    case DisturbanceKind::kBlackout:
      return "blackout";
    case DisturbanceKind::kOcclusion:
      return "occlusion";
    case DisturbanceKind::kBump:
      return "bump";
    case DisturbanceKind::kLeaveView:
      return "leaves the view";
  }
  return "?";
}

double Disturbance::backAt() const
{
  switch (kind)
  {
    case DisturbanceKind::kBump:
      return start_s + kBumpRampS;
    case DisturbanceKind::kLeaveView:
      return start_s + 2 * kTurnRampS + length_s;
    default:
      return start_s + length_s;
  }
}

Eigen::Matrix3d disturbanceRotation(const Disturbance& d, double t)
{
  double angle = 0;
  if (d.kind == DisturbanceKind::kBump)
    angle = d.angle_deg * smoothStep((t - d.start_s) / kBumpRampS);
  else if (d.kind == DisturbanceKind::kLeaveView)
    angle = d.angle_deg * (smoothStep((t - d.start_s) / kTurnRampS) -
                           smoothStep((t - d.start_s - kTurnRampS - d.length_s) / kTurnRampS));
  return Eigen::AngleAxisd(angle * kDeg, d.axis_camera).toRotationMatrix();
}

dvs_calibration::Pose DisturbedTrajectory::poseAt(double t) const
{
  const dvs_calibration::Pose p = base_->poseAt(t);
  return dvs_calibration::Pose::fromWorldCamera(Eigen::Matrix3d(p.R_world_camera() * disturbanceRotation(d_, t)),
                                                p.p_world_camera());
}

SweepScene buildReacquireScene(SweepSceneSpec spec)
{
  spec.flip_repeat_s = kFlipRepeatS;
  return buildSweepScene(spec);
}

Disturbance sweepDisturbance(const SweepScene& scene, int index, double edges_fire_s, double lead_s)
{
  Disturbance d;
  d.kind = static_cast<DisturbanceKind>(index % 4);
  std::mt19937_64 rng(scene.spec.seed * 7919 + 17);
  d.start_s = std::max(0.0, edges_fire_s) + lead_s;
  d.length_s = uniform(rng, 0.2, 1.0);
  const dvs_calibration::Pose at_start = scene.trajectory->poseAt(d.start_s);
  switch (d.kind)
  {
    case DisturbanceKind::kBlackout:
      break;
    case DisturbanceKind::kOcclusion:
    {
      // A line through the map's centre as seen at the start, at a random angle.
      Eigen::Vector2d c;
      if (!scene.camera.project(at_start.toCamera(scene.target), c))
        c = Eigen::Vector2d(scene.camera.width() / 2.0, scene.camera.height() / 2.0);
      const double a = uniform(rng, 0, 2 * M_PI);
      d.occluder_point = c;
      d.occluder_normal = Eigen::Vector2d(std::cos(a), std::sin(a));
      break;
    }
    case DisturbanceKind::kBump:
    {
      d.angle_deg = uniform(rng, 8, 20);
      Eigen::Vector3d axis(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      d.axis_camera = axis.norm() > 1e-6 ? axis.normalized() : Eigen::Vector3d::UnitY();
      break;
    }
    case DisturbanceKind::kLeaveView:
    {
      // Yaw or pitch, either way, until no part of the map is in the image (plus 10 deg).
      d.axis_camera = uniform(rng, 0, 1) < 0.5 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
      if (uniform(rng, 0, 1) < 0.5)
        d.axis_camera = -d.axis_camera;
      double angle = 0;
      while (angle < 150)
      {
        angle += 1;
        const dvs_calibration::Pose turned = dvs_calibration::Pose::fromWorldCamera(
            Eigen::Matrix3d(at_start.R_world_camera() * Eigen::AngleAxisd(angle * kDeg, d.axis_camera).toRotationMatrix()),
            at_start.p_world_camera());
        if (!mapInView(scene, turned))
          break;
      }
      d.angle_deg = angle + 10;
      break;
    }
  }
  return d;
}

DisturbedScene disturbSweepScene(const SweepScene& scene, int index)
{
  DisturbedScene out;
  out.edges_fire_s = edgesFireTime(scene, dvs_screen_sim::sampleTrajectory(*scene.trajectory, scene.duration, 1000.0));
  const Disturbance d = sweepDisturbance(scene, index, out.edges_fire_s);
  out.disturbance = d;
  SweepScene& ds = out.scene;
  ds = scene;
  ds.trajectory = std::make_shared<DisturbedTrajectory>(scene.trajectory, d);
  // Simulated until kTailS after the map's edges fire again (a slow camera needs a while to
  // draw them; at most kMaxWaitS).
  const double back_at = d.backAt();
  out.edges_refire_s = edgesFireTime(ds, dvs_screen_sim::sampleTrajectory(*ds.trajectory, back_at + kMaxWaitS, 1000.0),
                                     back_at, kRefireWindowS);
  ds.duration = (out.edges_refire_s >= 0 ? out.edges_refire_s : back_at + kMaxWaitS) + kTailS;
  out.events = simulateSweepScene(ds);
  const int64_t from_ns = std::llround(d.start_s * 1e9), to_ns = std::llround((d.start_s + d.length_s) * 1e9);
  if (d.kind == DisturbanceKind::kBlackout || d.kind == DisturbanceKind::kOcclusion)
    out.events.erase(std::remove_if(out.events.begin(), out.events.end(),
                                    [&](const dvs_driver::Event& e) {
                                      if (e.t_ns < from_ns || e.t_ns >= to_ns)
                                        return false;
                                      return d.kind == DisturbanceKind::kBlackout ||
                                             d.occluder_normal.dot(Eigen::Vector2d(e.x, e.y) - d.occluder_point) > 0;
                                    }),
                     out.events.end());
  return out;
}

ReacquireResult runReacquireScene(const SweepScene& scene, int index, const LineTrackerParams& params)
{
  ReacquireResult r;
  const DisturbedScene disturbed = disturbSweepScene(scene, index);
  const SweepScene& ds = disturbed.scene;
  const Disturbance& d = disturbed.disturbance;
  const dvs_driver::EventVector& events = disturbed.events;
  r.disturbance = d;
  r.edges_fire_s = disturbed.edges_fire_s;
  r.edges_refire_s = disturbed.edges_refire_s;
  const dvs_calibration::Trajectory gt = dvs_screen_sim::sampleTrajectory(*ds.trajectory, ds.duration, 1000.0);
  const double judge_from = r.edges_refire_s >= 0 ? r.edges_refire_s : 1e300;

  LineTracker tracker(ds.camera, ds.map, params);
  dvs_calibration::Trajectory estimates;
  estimates.reserve(events.size());
  bool tracking = false;
  uint64_t losses_at_start = 0;
  bool started = false;
  const double c0 = threadCpuSeconds();
  for (const auto& e : events)
  {
    const double t = e.t_ns * 1e-9;
    if (!started && t >= d.start_s)
    {
      started = true;
      losses_at_start = tracker.stats().losses;
    }
    const bool updated = tracker.processEvent(e);
    const bool now_tracking = tracker.state() == TrackerState::kTracking;
    if (updated)
    {
      estimates.push_back({t, tracker.pose()});
      const dvs_calibration::Pose truth = ds.trajectory->poseAt(t);
      if (t < d.start_s)
        r.tracking_before = now_tracking && poseWithin(ds, truth, tracker.pose(), 0.1, 10);
      else if (!tracking)
      {
        ++r.reinitializations;
        if (!poseWithin(ds, truth, tracker.pose(), 0.1, 10))
          ++r.false_reinitializations;
      }
      if (t >= judge_from && r.back_after_s < 0 && now_tracking && poseWithin(ds, truth, tracker.pose(), 0.05, 3))
        r.back_after_s = t - judge_from;
    }
    else if (t < d.start_s && !now_tracking)
      r.tracking_before = false;
    tracking = now_tracking;
  }
  r.tracker_cpu_s = threadCpuSeconds() - c0;
  r.kept = started && tracker.stats().losses == losses_at_start && r.reinitializations == 0;
  r.last_loss_reason = tracker.lastLossReason();
  r.init_stats = tracker.initializerStats();

  dvs_calibration::Trajectory gt_in_view;
  for (const auto& g : gt)
    if (g.t >= judge_from + kSettleS && visibleEdges(ds, g.T_world_camera) >= 3)
      gt_in_view.push_back(g);
  if (!estimates.empty() && !gt_in_view.empty())
  {
    const auto after = dvs_calibration::evaluateTrajectory(estimates, gt_in_view, sweepAccuracyOptions(ds));
    // evaluateTrajectory counts from the first estimate on: every sample here is after the
    // disturbance, so a track that never came back counts as untracked.
    r.tracked_after = after.samples > 0 ? static_cast<double>(after.samples_tracked) / gt_in_view.size() : 0.0;
    r.rms_after_ratio = after.rms_position_m / ds.distance;
  }
  return r;
}
}  // namespace dvs_line_tracker
