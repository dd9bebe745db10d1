#include "imu_flip_evaluation.h"

#include <dvs_line_tracker/body_odometry.h>

#include <Eigen/Cholesky>
#include <yaml-cpp/yaml.h>

namespace dvs_line_tracker
{
Pose FlipScene::truth(int64_t t_ns) const { return trajectory->poseAt((t_ns - config.time_offset_ns) * 1e-9); }

FlipScene simulateFlip(const std::string& overrides, uint64_t seed)
{
  FlipScene s;
  s.config = dvs_screen_sim::resolveSimConfig("flip", YAML::Load(overrides), seed);
  s.output = dvs_screen_sim::runSimulation(s.config);
  s.trajectory = dvs_screen_sim::makeTrajectory(s.config);
  for (const auto& g : s.output.groundtruth)
    s.ground_truth.push_back(g);
  return s;
}

namespace
{
void countConsistency(const FlipScene& s, int64_t t_ns, const Pose& estimate, const Matrix6d& cov,
                      const FlipRunOptions& options, FlipRunResult& r)
{
  Eigen::Vector3d dp, dr;
  r.consistency.add(s.truth(t_ns), estimate, cov, &dp, &dr);
  if (options.trace)
    std::fprintf(options.trace, "%.4f %.5f %.5f %.5f %.5f %.5f %.5f %.6f %.6f %.6f %.6f %.6f %.6f\n", t_ns * 1e-9,
                 dp.x(), dp.y(), dp.z(), std::sqrt(cov(3, 3)), std::sqrt(cov(4, 4)), std::sqrt(cov(5, 5)), dr.x(),
                 dr.y(), dr.z(), std::sqrt(cov(0, 0)), std::sqrt(cov(1, 1)), std::sqrt(cov(2, 2)));
}
}  // namespace

FlipRunResult runFlip(const FlipScene& s, const FlipRunOptions& options)
{
  LineTracker tracker(s.config.camera, defaultSquareMap(), options.params);
  std::shared_ptr<ImuPropagator> imu;
  if (options.use_imu)
  {
    imu = std::make_shared<ImuPropagator>(options.params.imu);
    tracker.setPropagator(imu);
  }
  const int64_t b0 = s.config.time_offset_ns + static_cast<int64_t>(options.blackout_from_s * 1e9);
  const int64_t b1 = b0 + static_cast<int64_t>(options.blackout_s * 1e9);
  FlipRunResult r;
  dvs_calibration::Trajectory estimates;
  estimates.reserve(s.output.events.size());
  size_t next_imu = 0;
  int64_t next_check_ns = 0;
  bool after_gap_measured = options.blackout_s <= 0;
  for (const auto& e : s.output.events)
  {
    while (imu && next_imu < s.output.imu.size() && s.output.imu[next_imu].t_ns <= e.t_ns)
    {
      dvs_driver::ImuSample sample = s.output.imu[next_imu++];
      if (options.imu_filter && !options.imu_filter(sample))
        continue;
      imu->addSample(sample);
      ImuOdometry odo;
      if (!imu->odometry(sample.t_ns, odo))
        continue;
      r.odometry_positive_definite &= Eigen::LLT<Matrix6d>(odo.pose_covariance).info() == Eigen::Success &&
                                      odo.velocity_covariance.llt().info() == Eigen::Success;
      // As ~odometry reports it: the filter's covariance plus the vision updates' lag.
      countConsistency(s, sample.t_ns, odo.T_world_camera, odo.pose_covariance + tracker.motionLagCovariance(), options, r);
    }
    // Vision alone: the tracker's pose against the covariance ~odometry reports, every 1 ms.
    if (!imu && tracker.state() == TrackerState::kTracking && e.t_ns >= next_check_ns)
    {
      countConsistency(s, e.t_ns, tracker.pose(), tracker.visionOnlyPoseCovariance(), options, r);
      next_check_ns = e.t_ns + 1000000;
    }
    if (options.blackout_s > 0 && e.t_ns >= b0 && e.t_ns < b1)
      continue;
    if (tracker.processEvent(e))
      estimates.push_back({e.t_ns * 1e-9, tracker.pose()});
    if (!after_gap_measured && e.t_ns >= b1)
    {
      after_gap_measured = true;
      if (tracker.state() == TrackerState::kTracking)
      {
        const Pose gt = s.truth(e.t_ns);
        r.after_gap_position_m = positionError(tracker.pose(), gt);
        r.after_gap_orientation_rad = orientationError(tracker.pose(), gt);
      }
    }
  }
  r.all = dvs_calibration::evaluateTrajectory(estimates, s.ground_truth, 0.05);
  if (options.blackout_s > 0)
    r.after = dvs_calibration::evaluateTrajectory(estimates, s.ground_truth, 0.05, b1 * 1e-9 + 0.001);
  r.stats = tracker.stats();
  if (imu)
  {
    r.imu_status = imu->status();
    r.imu_message = imu->statusMessage();
    r.gravity = imu->filter().gravity();
  }
  return r;
}
}  // namespace dvs_line_tracker
