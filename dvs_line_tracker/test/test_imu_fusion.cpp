// IMU fusion (issue 17) end to end on the software DVS's 1200 deg/s flip with its MPU-6150-class
// IMU (random initial biases): the IMU makes the tracker more accurate, bridges a blackout of
// every event in the middle of the flip, and a missing, late or absurd IMU stream falls back to
// vision alone without making tracking worse. Plus the filter's parts with known answers.
#include <dvs_line_tracker/imu_ekf.h>
#include <dvs_line_tracker/imu_propagator.h>
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_line_tracker/tracker_params.h>
#include <dvs_calibration/trajectory_accuracy.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/sim_config.h>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <functional>
#include <memory>

using namespace dvs_line_tracker;

namespace
{
struct Flip
{
  dvs_screen_sim::SimConfig config;
  dvs_screen_sim::SimulationOutput output;
  std::unique_ptr<dvs_screen_sim::Trajectory> trajectory;
  dvs_calibration::Trajectory ground_truth;
};

Flip makeFlip(const std::string& overrides, uint64_t seed)
{
  Flip s;
  s.config = dvs_screen_sim::resolveSimConfig("flip", YAML::Load(overrides), seed);
  s.output = dvs_screen_sim::runSimulation(s.config);
  s.trajectory = dvs_screen_sim::makeTrajectory(s.config);
  for (const auto& g : s.output.groundtruth)
    s.ground_truth.push_back(g);
  return s;
}

/// The 2.3 m flip of seed 2, simulated once for the whole binary.
const Flip& flip()
{
  static const Flip f = makeFlip("trajectory: {flip: {distance: 2.3}}", 2);
  return f;
}

using ImuFilter = std::function<bool(dvs_driver::ImuSample&)>;  ///< edits a sample; false drops it

struct Result
{
  dvs_calibration::AccuracyReport accuracy;
  TrackerStats stats;
  ImuStatus imu_status = ImuStatus::kWaiting;
  std::string imu_message;
  double after_gap_position_m = -1, after_gap_orientation_rad = -1;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< the filter's at the end
  bool odometry_positive_definite = true;
  uint64_t odometry_samples = 0;
};

/// Track the flip, with the IMU samples passed through `filter` (none: vision only), events in
/// [gap_from, gap_from + gap) s removed.
Result track(const ImuFilter* filter, double gap_from = 0, double gap = 0, const Flip& f = flip(),
             const LineTrackerParams& params = LineTrackerParams())
{
  LineTracker tracker(f.config.camera, defaultSquareMap(), params);
  std::shared_ptr<ImuPropagator> imu;
  if (filter)
  {
    imu = std::make_shared<ImuPropagator>(params.imu);
    tracker.setPropagator(imu);
  }
  Result r;
  dvs_calibration::Trajectory estimates;
  const int64_t g0 = static_cast<int64_t>(gap_from * 1e9), g1 = static_cast<int64_t>((gap_from + gap) * 1e9);
  bool gap_measured = gap <= 0;
  size_t next = 0;
  for (const auto& e : f.output.events)
  {
    while (imu && next < f.output.imu.size() && f.output.imu[next].t_ns <= e.t_ns)
    {
      dvs_driver::ImuSample s = f.output.imu[next++];
      if ((*filter)(s))
        imu->addSample(s);
      ImuOdometry o;
      if (imu->odometry(s.t_ns, o))
      {
        ++r.odometry_samples;
        r.odometry_positive_definite &= Eigen::LLT<Matrix6d>(o.pose_covariance).info() == Eigen::Success &&
                                        o.velocity_covariance.llt().info() == Eigen::Success;
      }
    }
    if (e.t_ns >= g0 && e.t_ns < g1)
      continue;
    if (tracker.processEvent(e))
      estimates.push_back({e.t_ns * 1e-9, tracker.pose()});
    if (!gap_measured && e.t_ns >= g1)
    {
      gap_measured = true;
      if (tracker.state() == TrackerState::kTracking)
      {
        const Pose gt = f.trajectory->poseAt(e.t_ns * 1e-9);
        r.after_gap_position_m = positionError(tracker.pose(), gt);
        r.after_gap_orientation_rad = orientationError(tracker.pose(), gt);
      }
    }
  }
  r.accuracy = dvs_calibration::evaluateTrajectory(estimates, f.ground_truth, 0.05);
  r.stats = tracker.stats();
  if (imu)
  {
    r.imu_status = imu->status();
    r.imu_message = imu->statusMessage();
    r.gravity = imu->filter().gravity();
  }
  return r;
}

const Result& visionOnly()
{
  static const Result r = track(nullptr);
  return r;
}

const ImuFilter kUnchanged = [](dvs_driver::ImuSample&) { return true; };
}  // namespace

TEST(ImuFusion, MoreAccurateThanVisionAloneOnTheFlip)
{
  const Result& v = visionOnly();
  const Result m = track(&kUnchanged);
  ASSERT_EQ(v.stats.losses, 0u);
  EXPECT_EQ(m.stats.losses, 0u);
  EXPECT_EQ(m.imu_status, ImuStatus::kOk) << m.imu_message;
  EXPECT_NEAR(m.accuracy.trackedFraction(), 1.0, 1e-9);
  // Benchmark (seeds 1-5): 24-49 % lower; here seed 2 at 2.3 m (35-45 % measured).
  EXPECT_LT(m.accuracy.rms_position_m, 0.8 * v.accuracy.rms_position_m)
      << "with IMU " << m.accuracy.rms_position_m << " m, without " << v.accuracy.rms_position_m << " m";
  EXPECT_LT(m.accuracy.rms_orientation_rad, v.accuracy.rms_orientation_rad);
  EXPECT_GT(m.odometry_samples, 1000u);
  EXPECT_TRUE(m.odometry_positive_definite);
}

TEST(ImuFusion, BridgesA150msBlackoutInTheFlip)
{
  // No event at all for 150 ms around the flip's peak rate (0.75 s).
  const Result v = track(nullptr, 0.675, 0.15);
  EXPECT_GE(v.stats.losses, 1u) << "without the IMU the stale pose must be declared lost";
  const Result m = track(&kUnchanged, 0.675, 0.15);
  EXPECT_EQ(m.stats.losses, 0u);
  EXPECT_EQ(m.stats.reinitializations, 0u);
  EXPECT_EQ(m.stats.gaps_bridged, 1u);
  ASSERT_GE(m.after_gap_position_m, 0) << "not tracking right after the blackout";
  EXPECT_LT(m.after_gap_position_m, 0.05);
  EXPECT_LT(m.after_gap_orientation_rad, 2.0 * M_PI / 180);
}

TEST(ImuFusion, SquareOnTheFloor)
{
  // The same flip with gravity along the world's z: the square on the floor, the camera above it
  // looking down. The camera accelerates sideways (0.9 m/s^2) when tracking starts, so the
  // gravity started from the accelerometer is 5 deg off.
  const Flip floor = makeFlip("trajectory: {flip: {distance: 2.3}}\nimu: {gravity: [0.0, 0.0, 9.81]}", 2);
  const Result v = track(nullptr, 0, 0, floor);
  // Given gravity: the IMU helps as on the wall.
  LineTrackerParams known;
  known.imu.gravity_world = "0 0 9.81";
  const Result k = track(&kUnchanged, 0, 0, floor, known);
  EXPECT_EQ(k.imu_status, ImuStatus::kOk) << k.imu_message;
  EXPECT_EQ(k.stats.losses, 0u);
  EXPECT_LT(k.accuracy.rms_position_m, 0.8 * v.accuracy.rms_position_m);
  // Estimated: the filter explains the wrong gravity with biases beyond their prior; the
  // plausibility check sets the IMU aside (vision alone) and says why. Known limitation: the
  // error before that (BENCHMARKS.md): 4.0 cm RMS instead of 2.9 without IMU on this sequence.
  const Result e = track(&kUnchanged, 0, 0, floor);
  EXPECT_EQ(e.imu_status, ImuStatus::kDisagrees) << e.imu_message;
  EXPECT_NE(e.imu_message.find("imu_gravity_world"), std::string::npos) << e.imu_message;
  EXPECT_EQ(e.stats.losses, 0u);
  EXPECT_LT(e.accuracy.rms_position_m, 2.0 * v.accuracy.rms_position_m);
}

TEST(ImuFusion, KnownGravityIsUsedAsGiven)
{
  LineTrackerParams params;
  params.imu.gravity_world = "0 -9.81 0";  // the simulator's wall: world y up
  const Result m = track(&kUnchanged, 0, 0, flip(), params);
  EXPECT_EQ(m.imu_status, ImuStatus::kOk) << m.imu_message;
  EXPECT_EQ(m.gravity, Eigen::Vector3d(0, -9.81, 0));
  EXPECT_LT(m.accuracy.rms_position_m, 0.8 * visionOnly().accuracy.rms_position_m);
}

// A misbehaving IMU: vision alone, said why, and no worse than without an IMU.
void expectFallback(const ImuFilter& filter, const char* what)
{
  SCOPED_TRACE(what);
  const Result& v = visionOnly();
  const Result m = track(&filter);
  EXPECT_NE(m.imu_status, ImuStatus::kOk);
  EXPECT_FALSE(m.imu_message.empty());
  EXPECT_LE(m.stats.losses, v.stats.losses);
  EXPECT_LT(m.accuracy.rms_position_m, 1.1 * v.accuracy.rms_position_m)
      << "with the bad IMU " << m.accuracy.rms_position_m << " m, without " << v.accuracy.rms_position_m << " m";
  EXPECT_NEAR(m.accuracy.trackedFraction(), 1.0, 1e-9);
}

TEST(ImuFusion, GyroscopeInDegreesPerSecondFallsBackToVision)
{
  expectFallback(
      [](dvs_driver::ImuSample& s) {
        for (double& g : s.gyro)
          g *= 180.0 / M_PI;
        return true;
      },
      "gyro in deg/s");
}

TEST(ImuFusion, AccelerometerInGFallsBackToVision)
{
  expectFallback(
      [](dvs_driver::ImuSample& s) {
        for (double& a : s.accel)
          a /= 9.81;
        return true;
      },
      "accelerometer in g");
}

TEST(ImuFusion, StuckAxisFallsBackToVision)
{
  expectFallback(
      [](dvs_driver::ImuSample& s) {
        s.gyro[2] = 0.0;  // the roll axis of the flip reads nothing
        return true;
      },
      "stuck gyro z");
}

TEST(ImuFusion, StreamThatStopsFallsBackToVision)
{
  expectFallback([](dvs_driver::ImuSample& s) { return s.t_ns < 400000000; }, "stream stops at 0.4 s");
}

TEST(ImuFusion, LateStreamFallsBackToVision)
{
  // Stamped 0.5 s behind the events: the newest sample is always older than imu_max_latency.
  expectFallback(
      [](dvs_driver::ImuSample& s) {
        s.t_ns -= 500000000;
        return true;
      },
      "stream 0.5 s late");
}

TEST(ImuEkf, KnownMotionWithPerfectMeasurementsFindsTheBiases)
{
  // A camera turning at a constant rate and accelerating, observed exactly: the filter's biases
  // converge to those added to the samples, its gravity to the true one.
  ImuFusionParams params;
  ImuExtrinsics x;
  ASSERT_EQ(parseImuExtrinsics(params, x), "");
  ImuEkf ekf(params, x);
  const Eigen::Vector3d g(0, -9.81, 0), w(0.4, -0.3, 1.2), a_world(0.3, 0.2, -0.1);
  const Eigen::Vector3d bg(0.008, -0.005, 0.003), ba(0.04, -0.03, 0.02);
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p(0, 0, -2), v(0, 0, 0);
  auto pose = [&] { return Pose::fromWorldCamera(R, p); };
  ekf.start(pose(), R.transpose() * (a_world - g) + ba, false);
  const double dt = 1e-3;
  Matrix6d cov = Matrix6d::Identity() * 1e-8;
  for (int k = 0; k < 5000; ++k)
  {
    const Eigen::Vector3d gyro = w + bg, accel = R.transpose() * (a_world - g) + ba;
    ekf.propagateMean(gyro, accel, dt);
    ekf.propagateCovariance(gyro, accel, dt);
    p += v * dt + 0.5 * a_world * dt * dt;
    v += a_world * dt;
    R = R * Eigen::AngleAxisd(w.norm() * dt, w.normalized()).toRotationMatrix();
    ekf.updateCameraPose(pose(), cov, 1e12);
  }
  EXPECT_LT((ekf.gyroBias() - bg).norm(), 1e-3);
  EXPECT_LT((ekf.accelBias() - ba).norm(), 0.01);
  EXPECT_LT((ekf.gravity() - g).norm(), 0.01);
  EXPECT_LT((ekf.velocity() - v).norm(), 0.01);
}

TEST(ImuEkf, CameraIncrementBetweenTwoPosesIsExact)
{
  const Pose a = dvs_calibration::lookAt(Eigen::Vector3d(0.3, -0.2, -2), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY());
  const Pose b = dvs_calibration::lookAt(Eigen::Vector3d(-0.5, 0.4, -1.5), Eigen::Vector3d(0.1, 0, 0),
                                         Eigen::Vector3d::UnitY(), 2.5);
  Pose c = a;
  c.applyCameraIncrement(cameraIncrementBetween(a, b));
  EXPECT_LT(positionError(c, b), 1e-9);
  EXPECT_LT(orientationError(c, b), 1e-9);
}

TEST(ImuFusionParams, BadVectorsAreNamed)
{
  ImuFusionParams p;
  ImuExtrinsics x;
  p.q_camera_imu = "0 0 1";
  EXPECT_NE(parseImuExtrinsics(p, x).find("imu_q_camera_imu"), std::string::npos);
  p.q_camera_imu = "0 0 0 2";
  EXPECT_NE(parseImuExtrinsics(p, x).find("unit quaternion"), std::string::npos);
  p = ImuFusionParams();
  p.gravity_world = "0 -1 0";
  EXPECT_NE(parseImuExtrinsics(p, x).find("imu_gravity_world"), std::string::npos);
  p.gravity_world = "0, -9.81, 0";
  EXPECT_EQ(parseImuExtrinsics(p, x), "");
  ASSERT_TRUE(x.gravity_world.has_value());
  EXPECT_DOUBLE_EQ(x.gravity_world->y(), -9.81);
  LineTrackerParams t;
  t.imu.p_camera_imu = "a b c";
  EXPECT_NE(validateParams(t).find("imu_p_camera_imu"), std::string::npos);
}
