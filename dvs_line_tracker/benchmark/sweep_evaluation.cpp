#include "sweep_evaluation.h"

#include "benchmark_stats.h"

#include <dvs_calibration/trajectory_accuracy.h>
#include <dvs_calibration/trajectory_file.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_line_tracker/body_odometry.h>
#include <dvs_line_tracker/line_tracker.h>

#include <algorithm>
#include <ctime>
#include <fstream>
#include <limits>

namespace dvs_line_tracker
{
namespace
{
constexpr double kDeg = 180.0 / M_PI;
constexpr double kMinVisiblePx = 10.0;

/// Whether world point `pw` projects into the (distorted) image at `pose`; its pixel into `px`.
bool projectsIntoImage(const dvs_calibration::CameraModel& camera, const dvs_calibration::Pose& pose,
                       const Eigen::Vector3d& pw, Eigen::Vector2d& px)
{
  return camera.project(pose.toCamera(pw), px) && px.x() >= -0.5 && px.y() >= -0.5 &&
         px.x() <= camera.width() - 0.5 && px.y() <= camera.height() - 0.5;
}

/// Length [px] of the part of a map segment that projects into the (distorted) image.
double visibleLength(const dvs_calibration::CameraModel& camera, const dvs_calibration::Pose& pose, const MapSegment& seg)
{
  constexpr int kSamples = 24;
  Eigen::Vector2d prev;
  bool prev_in = false;
  double length = 0;
  for (int i = 0; i <= kSamples; ++i)
  {
    const Eigen::Vector3d pw = seg.p0_world + (seg.p1_world - seg.p0_world) * (static_cast<double>(i) / kSamples);
    Eigen::Vector2d px;
    const bool in = projectsIntoImage(camera, pose, pw, px);
    if (in && prev_in)
      length += (px - prev).norm();
    prev = px;
    prev_in = in;
  }
  return length;
}

}  // namespace

bool mapInView(const SweepScene& s, const dvs_calibration::Pose& pose)
{
  constexpr int kSamples = 32;
  for (const auto& seg : s.map.segments)
    for (int i = 0; i <= kSamples; ++i)
    {
      Eigen::Vector2d px;
      if (projectsIntoImage(s.camera, pose,
                            seg.p0_world + (seg.p1_world - seg.p0_world) * (static_cast<double>(i) / kSamples), px))
        return true;
    }
  return false;
}

bool poseWithin(const SweepScene& s, const dvs_calibration::Pose& truth, const dvs_calibration::Pose& estimate,
                double distance_ratio, double angle_deg)
{
  const double distance = (truth.p_world_camera() - s.target).norm();
  return positionError(truth, estimate) <= distance_ratio * distance &&
         orientationError(truth, estimate) * kDeg <= angle_deg;
}

dvs_calibration::AccuracyOptions sweepAccuracyOptions(const SweepScene& s)
{
  dvs_calibration::AccuracyOptions accuracy;
  accuracy.max_age_s = 0.05;
  accuracy.max_position_m = 0.1 * s.distance;
  accuracy.max_orientation_rad = 10.0 / kDeg;
  return accuracy;
}

int visibleEdges(const SweepScene& s, const dvs_calibration::Pose& pose)
{
  int n = 0;
  for (const auto& seg : s.map.segments)
    n += visibleLength(s.camera, pose, seg) >= kMinVisiblePx ? 1 : 0;
  return n;
}

// An edge's sweep: the mean normal motion of its end points in ideal pixels.
double edgesFireTime(const SweepScene& s, const dvs_calibration::Trajectory& gt, double from_s, double window_s)
{
  const size_t n = s.map.segments.size();
  // Per edge, the sweep accumulated since from_s, and its value at every sample (to subtract
  // the part older than window_s).
  std::vector<double> swept(n, 0.0);
  std::vector<std::vector<std::pair<double, double>>> history(n);
  std::vector<size_t> oldest(n, 0);
  std::vector<Eigen::Vector2d> a_prev(n), b_prev(n);
  std::vector<char> have(n, 0);
  const size_t needed = std::min<size_t>(3, n);
  for (const auto& sample : gt)
  {
    if (sample.t < from_s)
      continue;
    size_t fired = 0;
    for (size_t i = 0; i < n; ++i)
    {
      const auto& seg = s.map.segments[i];
      Eigen::Vector2d a, b;
      const bool ok = s.camera.projectIdeal(sample.T_world_camera.toCamera(seg.p0_world), a) &&
                      s.camera.projectIdeal(sample.T_world_camera.toCamera(seg.p1_world), b);
      const bool visible = ok && visibleLength(s.camera, sample.T_world_camera, seg) >= kMinVisiblePx;
      if (visible && have[i] && (b_prev[i] - a_prev[i]).norm() > 1e-9)
      {
        const Eigen::Vector2d d = (b_prev[i] - a_prev[i]).normalized();
        const Eigen::Vector2d normal(-d.y(), d.x());
        swept[i] += 0.5 * (std::abs(normal.dot(a - a_prev[i])) + std::abs(normal.dot(b - b_prev[i])));
      }
      have[i] = ok;
      a_prev[i] = a;
      b_prev[i] = b;
      double recent = swept[i];
      if (window_s > 0)
      {
        history[i].emplace_back(sample.t, swept[i]);
        while (history[i][oldest[i]].first < sample.t - window_s)
          ++oldest[i];
        recent -= history[i][oldest[i]].second;
      }
      fired += visible && recent >= 1.0 ? 1 : 0;
    }
    if (fired >= needed)
      return sample.t;
  }
  return -1;
}

dvs_driver::EventVector simulateSweepScene(const SweepScene& s, double* cpu_s)
{
  dvs_driver::EventVector events;
  const double c0 = threadCpuSeconds();
  dvs_screen_sim::EventSimulator sim(s.camera, s.scene, s.events, dvs_screen_sim::SamplingConfig(), s.spec.seed);
  sim.start(*s.trajectory);
  sim.advanceTo(s.duration, events);
  sim.flush(events);
  if (cpu_s)
    *cpu_s = threadCpuSeconds() - c0;
  return events;
}

void writeSweepSceneFiles(const std::string& dir, const SweepScene& scene, const dvs_driver::EventVector& events)
{
  dvs_driver::writeEventsText(dir + "/events.txt", events);
  dvs_calibration::writeTumTrajectory(dir + "/groundtruth.txt",
                                      dvs_screen_sim::sampleTrajectory(*scene.trajectory, scene.duration, 1000.0));
  const auto& k = scene.camera.intrinsics();
  std::ofstream(dir + "/calib.txt") << k.fx << " " << k.fy << " " << k.cx << " " << k.cy << " " << k.k1 << " " << k.k2
                                    << " " << k.p1 << " " << k.p2 << " " << k.k3 << "\n";
  std::ofstream(dir + "/size.txt") << k.width << " " << k.height << "\n";
  std::ofstream(dir + "/map.yaml") << lineMapToYaml(scene.map);
}

SweepResult runSweepScene(const SweepScene& s, const LineTrackerParams& params)
{
  SweepResult r;
  const dvs_driver::EventVector events = simulateSweepScene(s, &r.simulator_cpu_s);
  r.events = events.size();
  const dvs_calibration::Trajectory gt = dvs_screen_sim::sampleTrajectory(*s.trajectory, s.duration, 1000.0);
  r.edges_fire_s = edgesFireTime(s, gt);

  LineTracker tracker(s.camera, s.map, params);
  dvs_calibration::Trajectory estimates;
  estimates.reserve(events.size());
  const double c0 = threadCpuSeconds();
  bool tracking = false;
  int64_t next_consistency_ns = std::numeric_limits<int64_t>::min();
  for (const auto& e : events)
  {
    const bool updated = tracker.processEvent(e);
    const bool now_tracking = tracker.state() == TrackerState::kTracking;
    if (now_tracking && e.t_ns >= next_consistency_ns)
    {
      next_consistency_ns = e.t_ns + 1000000;
      const dvs_calibration::Pose truth = s.trajectory->poseAt(e.t_ns * 1e-9);
      r.consistency.add(truth, tracker.pose(), tracker.visionOnlyPoseCovariance());
      r.consistency_without_lag.add(truth, tracker.pose(),
                                    visionPoseCovariance(tracker.estimatorState()) * kVisionOnlyCovarianceScale);
    }
    if (updated)
    {
      const double t = e.t_ns * 1e-9;
      estimates.push_back({t, tracker.pose()});
      if (!tracking)
      {
        // A (re-)initialisation: compare it with the truth at its event's time.
        const dvs_calibration::Pose truth = s.trajectory->poseAt(t);
        ++r.initializations;
        if (!poseWithin(s, truth, tracker.pose(), 0.1, 10))
          ++r.false_initializations;
        if (r.first_pose_s < 0)
        {
          r.first_pose_s = t;
          r.first_pose_correct = poseWithin(s, truth, tracker.pose(), 0.05, 3);
        }
      }
    }
    tracking = now_tracking;
  }
  r.tracker_cpu_s = threadCpuSeconds() - c0;
  r.losses = static_cast<int>(tracker.stats().losses);
  r.partial_views_held = tracker.stats().partial_views_held;
  r.partial_views_resumed = tracker.stats().partial_views_resumed;
  r.partial_view_held_s = tracker.stats().partial_view_held_s;
  r.events_outside_sensor = tracker.stats().events_outside_sensor;
  r.init_stats = tracker.initializerStats();
  r.last_loss_reason = tracker.lastLossReason();
  if (r.first_pose_s >= 0 && r.edges_fire_s >= 0)
    r.first_pose_delay_s = r.first_pose_s - r.edges_fire_s;

  // Tracked fraction: the ground-truth samples with at least three map edges in view.
  dvs_calibration::Trajectory gt_in_view;
  for (const auto& g : gt)
    if (visibleEdges(s, g.T_world_camera) >= 3)
      gt_in_view.push_back(g);
  const dvs_calibration::AccuracyOptions accuracy = sweepAccuracyOptions(s);
  if (!estimates.empty())
  {
    const auto in_view = dvs_calibration::evaluateTrajectory(estimates, gt_in_view, accuracy);
    r.tracked_fraction = in_view.trackedFraction();
    const auto all = dvs_calibration::evaluateTrajectory(estimates, gt, accuracy);
    r.rms_position_m = all.rms_position_m;
    r.rms_orientation_deg = all.rms_orientation_rad * kDeg;
    r.max_position_m = all.max_position_m;
    r.rms_position_ratio = all.rms_position_m / s.distance;
  }
  return r;
}
}  // namespace dvs_line_tracker
