// The software DVS's IMU (imu_simulator.h): known answers without noise (a still camera reads
// +|g| upwards, the flip's gyro is its roll rate, a circling camera's centripetal acceleration,
// lever arm and rotated IMU axes), the noise's statistics (white noise std = density * sqrt(rate),
// bias random walk growing as walk * sqrt(t)), seeding, and the configuration and dataset paths.
#include <dvs_driver/imu_text_io.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/imu_simulator.h>
#include <dvs_screen_sim/sim_config.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace dvs_screen_sim;

namespace
{
ImuSimParams noiseFree()
{
  ImuSimParams p;
  p.gyro_noise_density = p.gyro_random_walk = p.accel_noise_density = p.accel_random_walk = 0;
  p.initial_gyro_bias = Eigen::Vector3d::Zero();
  p.initial_accel_bias = Eigen::Vector3d::Zero();
  return p;
}

Eigen::Vector3d vec(const double v[3]) { return Eigen::Vector3d(v[0], v[1], v[2]); }

/// Circles the wall's normal at radius r and rate w (rad/s), yawing with it about world z:
/// p = (r cos wt, r sin wt, d), R_world_camera = Rz(wt) * R_look. Known answers: body rate
/// R_camera_world (0, 0, w), acceleration -w^2 (r cos wt, r sin wt, 0).
class CirclingTrajectory : public Trajectory
{
public:
  CirclingTrajectory(double r, double w, double d) : r_(r), w_(w), d_(d) {}
  Pose poseAt(double t) const override
  {
    const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(w_ * t, Eigen::Vector3d::UnitZ())) *
                                 lookingAtWallOrientation();
    return Pose::fromWorldCamera(q, Eigen::Vector3d(r_ * std::cos(w_ * t), r_ * std::sin(w_ * t), d_));
  }
  double r_, w_, d_;
};

/// A camera at a fixed place spinning about its optical axis at rate w.
class SpinningTrajectory : public Trajectory
{
public:
  explicit SpinningTrajectory(double w) : w_(w) {}
  Pose poseAt(double t) const override
  {
    return Pose::fromWorldCamera(lookingAtWallOrientation() * Eigen::AngleAxisd(w_ * t, Eigen::Vector3d::UnitZ()),
                                 Eigen::Vector3d(0.1, 0.2, 1.5));
  }
  double w_;
};

double stddev(const std::vector<double>& v, double* mean_out = nullptr)
{
  double m = 0;
  for (double x : v)
    m += x;
  m /= v.size();
  double s = 0;
  for (double x : v)
    s += (x - m) * (x - m);
  if (mean_out)
    *mean_out = m;
  return std::sqrt(s / (v.size() - 1));
}

std::string slurp(const std::string& path)
{
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST(ImuSimulator, StillCameraReadsGravityUpwards)
{
  // Looking at the wall: camera y points down (world -y), so +9.81 along world +y is -9.81 on y.
  const StaticTrajectory still(Pose::fromWorldCamera(lookingAtWallOrientation(), Eigen::Vector3d(0.2, -0.1, 2.0)));
  const ImuTruth t = idealImu(still, 0.3, noiseFree());
  EXPECT_LT(t.gyro.norm(), 1e-12);
  EXPECT_NEAR(t.accel.x(), 0.0, 1e-9);
  EXPECT_NEAR(t.accel.y(), -9.81, 1e-9);
  EXPECT_NEAR(t.accel.z(), 0.0, 1e-9);
  // Any orientation: the specific force is R_camera_world (0, +9.81, 0), |f| = 9.81.
  const Eigen::Quaterniond q = orientationFromYawPitchRollDeg({20, -35, 60});
  const StaticTrajectory tilted(Pose::fromWorldCamera(q, Eigen::Vector3d(0, 0, 1)));
  const ImuTruth u = idealImu(tilted, 1.0, noiseFree());
  EXPECT_LT((u.accel - q.conjugate() * Eigen::Vector3d(0, 9.81, 0)).norm(), 1e-9);
  EXPECT_NEAR(u.accel.norm(), 9.81, 1e-9);
  // Another gravity direction (a parameter): the wall lying on the floor, g along world -z.
  ImuSimParams p = noiseFree();
  p.gravity = Eigen::Vector3d(0, 0, -9.81);
  EXPECT_LT((idealImu(still, 0.0, p).accel - Eigen::Vector3d(0, 0, -9.81)).norm(), 1e-9);  // camera z = world -z
}

TEST(ImuSimulator, FlipGyroIsTheRollRate)
{
  FlipTrajectoryParams fp;
  const FlipTrajectory flip(fp);
  double peak = 0;
  for (double t = 0.0; t <= 1.5; t += 0.005)
  {
    const ImuTruth truth = idealImu(flip, t, noiseFree());
    ASSERT_NEAR(truth.gyro.z(), flip.rollRateAt(t), 1e-5) << t;
    ASSERT_NEAR(truth.gyro.x(), 0.0, 1e-7) << t;
    ASSERT_NEAR(truth.gyro.y(), 0.0, 1e-7) << t;
    peak = std::max(peak, std::abs(truth.gyro.z()));
  }
  EXPECT_NEAR(peak, 1200.0 * M_PI / 180.0, 0.01);  // the flip's 1200 deg/s
}

TEST(ImuSimulator, FlipSpecificForceMatchesAFourthOrderDerivativeOfTheGroundTruth)
{
  // The ground truth's acceleration by a 5-point stencil (another step, another order), then
  // f = R_camera_world (a - g).
  const FlipTrajectory flip{FlipTrajectoryParams()};
  const double h = 2e-3;
  const Eigen::Vector3d g(0, -9.81, 0);
  for (double t = 0.05; t <= 1.45; t += 0.01)
  {
    auto p = [&](double s) { return flip.poseAt(s).p_world_camera(); };
    const Eigen::Vector3d a = (-p(t + 2 * h) + 16 * p(t + h) - 30 * p(t) + 16 * p(t - h) - p(t - 2 * h)) / (12 * h * h);
    const Eigen::Vector3d expected = flip.poseAt(t).R_camera_world * (a - g);
    ASSERT_LT((idealImu(flip, t, noiseFree()).accel - expected).norm(), 2e-4) << t;
  }
}

TEST(ImuSimulator, CirclingCameraKnownAnswers)
{
  const double r = 0.3, w = 2.0;
  const CirclingTrajectory circle(r, w, 1.5);
  for (double t : {0.0, 0.4, 1.7})
  {
    const Pose pose = circle.poseAt(t);
    const ImuTruth truth = idealImu(circle, t, noiseFree());
    // Body rate: yaw about world z, i.e. about the camera's -z (the camera looks along world -z).
    EXPECT_LT((truth.gyro - Eigen::Vector3d(0, 0, -w)).norm(), 1e-7) << t;
    const Eigen::Vector3d a_world(-w * w * r * std::cos(w * t), -w * w * r * std::sin(w * t), 0);
    EXPECT_LT((truth.accel - pose.R_camera_world * (a_world - Eigen::Vector3d(0, -9.81, 0))).norm(), 1e-6) << t;
  }
}

TEST(ImuSimulator, LeverArmAndRotatedImuAxes)
{
  // Spinning about the optical axis at w with the IMU 0.1 m along camera x: centripetal
  // -w^2 * 0.1 along the IMU's x (towards the axis), on top of gravity.
  const double w = 5.0;
  const SpinningTrajectory spin(w);
  ImuSimParams p = noiseFree();
  p.p_camera_imu = Eigen::Vector3d(0.1, 0, 0);
  for (double t : {0.0, 0.3})
  {
    const ImuTruth truth = idealImu(spin, t, p);
    const Eigen::Vector3d gravity_part = spin.poseAt(t).R_camera_world * Eigen::Vector3d(0, 9.81, 0);
    EXPECT_LT((truth.accel - (gravity_part + Eigen::Vector3d(-w * w * 0.1, 0, 0))).norm(), 1e-6) << t;
    EXPECT_LT((truth.gyro - Eigen::Vector3d(0, 0, w)).norm(), 1e-7) << t;
  }
  // IMU axes turned by 90 deg about the camera's x (R_camera_imu maps IMU axes to camera axes):
  // w_imu = R_imu_camera (0, 0, w) = (0, w, 0).
  p.p_camera_imu.setZero();
  p.q_camera_imu = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  const ImuTruth turned = idealImu(spin, 0.2, p);
  EXPECT_LT((turned.gyro - Eigen::Vector3d(0, w, 0)).norm(), 1e-7);
  const Eigen::Vector3d f_camera = spin.poseAt(0.2).R_camera_world * Eigen::Vector3d(0, 9.81, 0);
  EXPECT_LT((turned.accel - p.q_camera_imu.conjugate() * f_camera).norm(), 1e-7);  // second differences' rounding
}

TEST(ImuSimulator, HeldEndPosesPutNoImpulseIntoTheFirstAndLastSamples)
{
  // The linear trajectory moves at constant velocity from t = 0 to its duration and holds its end
  // poses outside: a central difference across t = 0 would read 0.4 m/s / 0.1 ms. Inside the
  // run's range the IMU reads gravity only (the orientation's rate is smooth).
  const LinearTrajectory linear{LinearTrajectoryParams()};
  dvs_driver::ImuVector s;
  simulateImu(linear, 2.0, noiseFree(), 0, 0, s);
  ASSERT_EQ(s.size(), 2001u);
  for (size_t k = 0; k < s.size(); k += (k < 3 || k > 1995) ? 1 : 97)
  {
    const Pose pose = linear.poseAt(static_cast<double>(k) / 1000.0);
    EXPECT_LT((vec(s[k].accel) - pose.R_camera_world * Eigen::Vector3d(0, 9.81, 0)).norm(), 1e-5) << k;
    EXPECT_LT(vec(s[k].gyro).norm(), 0.5) << k;  // the ypr interpolation turns at ~0.2 rad/s
  }
  // Unbounded, the first sample sees the start's velocity jump.
  EXPECT_GT((idealImu(linear, 0.0, noiseFree()).accel - vec(s[0].accel)).norm(), 100.0);
}

TEST(ImuSimulator, StampsCountAndNoiseFreeSamplesAreTheTruth)
{
  const FlipTrajectory flip{FlipTrajectoryParams()};
  dvs_driver::ImuVector s, b;
  simulateImu(flip, 0.25, noiseFree(), 1, 5000, s, &b);
  ASSERT_EQ(s.size(), 251u);  // 1 kHz over 0.25 s, both ends
  ASSERT_EQ(b.size(), s.size());
  for (size_t k = 0; k < s.size(); ++k)
  {
    ASSERT_EQ(s[k].t_ns, 5000 + static_cast<int64_t>(k) * 1000000);
    const ImuTruth truth = idealImu(flip, static_cast<double>(k) / 1000.0, noiseFree(), 0.0, 0.25);
    ASSERT_EQ(vec(s[k].gyro), truth.gyro);
    ASSERT_EQ(vec(s[k].accel), truth.accel);
    ASSERT_EQ(vec(b[k].gyro), Eigen::Vector3d::Zero());
  }
  // Streaming in pieces gives the same samples.
  ImuSimulator sim(noiseFree(), 1);
  sim.setTimeRange(0.0, 0.25);
  dvs_driver::ImuVector pieces;
  for (double t = 0.0137; t < 0.25; t += 0.0137)
    sim.advanceTo(flip, t, 5000, pieces);
  sim.advanceTo(flip, 0.25, 5000, pieces);
  EXPECT_EQ(pieces, s);
}

TEST(ImuSimulator, WhiteNoiseStdIsDensityTimesSqrtRate)
{
  // Defaults (MPU-6150 class) without bias: 100 000 samples at 1 kHz; sigma_d = density * sqrt(1000).
  ImuSimParams p;
  p.gyro_random_walk = p.accel_random_walk = 0;
  p.initial_gyro_bias = Eigen::Vector3d::Zero();
  p.initial_accel_bias = Eigen::Vector3d::Zero();
  const StaticTrajectory still(Pose::fromWorldCamera(lookingAtWallOrientation(), Eigen::Vector3d(0, 0, 2)));
  dvs_driver::ImuVector s;
  simulateImu(still, 99.999, p, 7, 0, s);
  ASSERT_EQ(s.size(), 100000u);
  const double sg = 1.7e-4 * std::sqrt(1000.0), sa = 2e-3 * std::sqrt(1000.0);
  EXPECT_DOUBLE_EQ(p.gyroSigma(), sg);
  EXPECT_DOUBLE_EQ(p.accelSigma(), sa);
  const Eigen::Vector3d f(0, -9.81, 0);
  for (int i = 0; i < 3; ++i)
  {
    std::vector<double> g, a;
    for (const auto& m : s)
    {
      g.push_back(m.gyro[i]);
      a.push_back(m.accel[i]);
    }
    double mg, ma;
    EXPECT_NEAR(stddev(g, &mg), sg, 0.03 * sg) << "gyro axis " << i;  // within 3 % (the brief: 10 %)
    EXPECT_NEAR(stddev(a, &ma), sa, 0.03 * sa) << "accel axis " << i;
    EXPECT_NEAR(mg, 0.0, 5 * sg / std::sqrt(1e5));
    EXPECT_NEAR(ma, f[i], 5 * sa / std::sqrt(1e5));
  }
}

TEST(ImuSimulator, BiasRandomWalkGrowsAsTheSquareRootOfTime)
{
  // No white noise: measurement - truth = the bias in force. Over 300 seeds, the spread of the
  // bias after T seconds is walk * sqrt(T) per axis (T = 0.25 and 1: it doubles).
  ImuSimParams p = noiseFree();
  p.gyro_random_walk = 2e-5;
  p.accel_random_walk = 3e-3;
  const StaticTrajectory still(Pose::fromWorldCamera(lookingAtWallOrientation(), Eigen::Vector3d(0, 0, 2)));
  std::vector<double> g_quarter, g_end, a_quarter, a_end;
  for (uint64_t seed = 0; seed < 300; ++seed)
  {
    dvs_driver::ImuVector s, b;
    simulateImu(still, 1.0, p, seed, 0, s, &b);
    ASSERT_EQ(s.size(), 1001u);
    for (int i = 0; i < 3; ++i)
    {
      ASSERT_EQ(s.back().gyro[i], b.back().gyro[i]);  // truth 0
      ASSERT_NEAR(s.back().accel[i] - (i == 1 ? -9.81 : 0.0), b.back().accel[i], 1e-12);
      g_quarter.push_back(b[250].gyro[i]);
      a_quarter.push_back(b[250].accel[i]);
      g_end.push_back(b[1000].gyro[i]);
      a_end.push_back(b[1000].accel[i]);
    }
    ASSERT_EQ(vec(b[0].gyro), Eigen::Vector3d::Zero());  // the given initial bias
  }
  // 900 values each: the std's own error is ~2.4 %; 10 % tolerance.
  EXPECT_NEAR(stddev(g_quarter), 2e-5 * 0.5, 0.1 * 2e-5 * 0.5);
  EXPECT_NEAR(stddev(g_end), 2e-5, 0.1 * 2e-5);
  EXPECT_NEAR(stddev(a_quarter), 3e-3 * 0.5, 0.1 * 3e-3 * 0.5);
  EXPECT_NEAR(stddev(a_end), 3e-3, 0.1 * 3e-3);
}

TEST(ImuSimulator, InitialBiasesAreSeededAndBounded)
{
  ImuSimParams p;
  const ImuSimulator a(p, 3), b(p, 3), c(p, 4);
  EXPECT_EQ(a.gyroBias(), b.gyroBias());
  EXPECT_EQ(a.accelBias(), b.accelBias());
  EXPECT_NE(a.gyroBias(), c.gyroBias());
  double largest_g = 0, largest_a = 0;
  for (uint64_t seed = 0; seed < 200; ++seed)
  {
    const ImuSimulator s(p, seed);
    ASSERT_LE(s.gyroBias().norm(), 0.01 + 1e-15);
    ASSERT_LE(s.accelBias().norm(), 0.05 + 1e-15);
    largest_g = std::max(largest_g, s.gyroBias().norm());
    largest_a = std::max(largest_a, s.accelBias().norm());
  }
  EXPECT_GT(largest_g, 0.009);  // the bound is reached, not just respected
  EXPECT_GT(largest_a, 0.045);
  p.initial_gyro_bias = Eigen::Vector3d(0.001, -0.002, 0.003);
  EXPECT_EQ(ImuSimulator(p, 9).gyroBias(), *p.initial_gyro_bias);
}

TEST(ImuConfig, DefaultsOverridesAndErrorsNameTheParameter)
{
  const SimConfig d = resolveSimConfig("flip", YAML::Node(), 0, 0.1);
  EXPECT_EQ(d.imu.rate, 1000.0);
  EXPECT_EQ(d.imu.gyro_noise_density, 1.7e-4);
  EXPECT_EQ(d.imu.gyro_random_walk, 2e-5);
  EXPECT_EQ(d.imu.accel_noise_density, 2e-3);
  EXPECT_EQ(d.imu.accel_random_walk, 3e-3);
  EXPECT_EQ(d.imu.initial_gyro_bias_max, 0.01);
  EXPECT_EQ(d.imu.initial_accel_bias_max, 0.05);
  EXPECT_FALSE(d.imu.initial_gyro_bias.has_value());
  EXPECT_EQ(d.imu.gravity, Eigen::Vector3d(0, -9.81, 0));
  EXPECT_TRUE(d.imu.q_camera_imu.isApprox(Eigen::Quaterniond::Identity()));
  const SimConfig o = resolveSimConfig(
      "flip", YAML::Load("{imu: {rate: 200, initial_gyro_bias: [0.1, 0, 0], gravity: [0, 0, -9.8], "
                         "extrinsic_rotation: [0, 0, 1, 1], extrinsic_translation: [0.01, 0.02, 0.03]}}"),
      0, 0.1);
  EXPECT_EQ(o.imu.rate, 200.0);
  EXPECT_EQ(*o.imu.initial_gyro_bias, Eigen::Vector3d(0.1, 0, 0));
  EXPECT_EQ(o.imu.gravity, Eigen::Vector3d(0, 0, -9.8));
  EXPECT_NEAR(o.imu.q_camera_imu.z(), std::sqrt(0.5), 1e-12);  // normalised
  EXPECT_EQ(o.imu.p_camera_imu, Eigen::Vector3d(0.01, 0.02, 0.03));
  auto error = [](const std::string& yaml) {
    try
    {
      resolveSimConfig("flip", YAML::Load(yaml), 0, 0.1);
    }
    catch (const ConfigError& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("{imu: {rate: 0}}").find("rate"), std::string::npos);
  EXPECT_NE(error("{imu: {gyro_noise_density: -1}}").find("gyro_noise_density"), std::string::npos);
  EXPECT_NE(error("{imu: {rate: fast}}").find("imu.rate"), std::string::npos);
  EXPECT_NE(error("{imu: {gravity: [0, 1]}}").find("imu.gravity"), std::string::npos);
  EXPECT_NE(error("{imu: {extrinsic_rotation: [0, 0, 0]}}").find("imu.extrinsic_rotation"), std::string::npos);
  EXPECT_NE(error("{imu: {extrinsic_rotation: [0, 0, 0, 0]}}").find("imu.extrinsic_rotation"), std::string::npos);
  EXPECT_NE(error("{imu: {initial_accel_bias: [0, .nan, 0]}}").find("imu.initial_accel_bias"), std::string::npos);
  EXPECT_NE(error("{imu: {noise: 1}}").find("unknown configuration parameter 'imu.noise'"), std::string::npos);
}

TEST(ImuDataset, ImuFilesAreWrittenReproducibleAndLeaveTheEventsAlone)
{
  const SimConfig c = resolveSimConfig("flip", YAML::Load("{time_offset: 0.5}"), 2, 0.1);
  const SimulationOutput out = runSimulation(c);
  ASSERT_EQ(out.imu.size(), 101u);
  ASSERT_EQ(out.imu_bias.size(), 101u);
  EXPECT_EQ(out.imu.front().t_ns, 500000000);  // the events' time base (offset included)
  const auto dir = (std::filesystem::temp_directory_path() / ("dvs_imu_dataset_" + std::to_string(::getpid()))).string();
  writeDataset(dir, c, out);
  EXPECT_EQ(dvs_driver::readImuText(dir + "/imu.txt"), out.imu);
  EXPECT_EQ(dvs_driver::readImuText(dir + "/imu_bias_groundtruth.txt"), out.imu_bias);
  EXPECT_EQ(slurp(dir + "/imu_bias_groundtruth.txt").rfind("# t bax bay baz bgx bgy bgz", 0), 0u);
  // The seed gives the same IMU; the IMU's parameters do not change the events.
  EXPECT_EQ(runSimulation(c).imu, out.imu);
  const SimConfig other = resolveSimConfig("flip", YAML::Load("{time_offset: 0.5, imu: {rate: 333}}"), 2, 0.1);
  const SimulationOutput o = runSimulation(other);
  EXPECT_EQ(o.events, out.events);
  EXPECT_EQ(o.imu.size(), 34u);  // 0, 3.003 ms, ..., 99.1 ms
  // Re-running from config.yaml reproduces imu.txt (the random initial biases come from the seed).
  const SimConfig again = resolveSimConfigFile("flip", dir + "/config.yaml");
  EXPECT_EQ(runSimulation(again).imu, out.imu);
  std::filesystem::remove_all(dir);
}
