// Known answers for the suite's one accuracy metric (trajectory_accuracy.h), round trips and
// errors of the TUM trajectory files (trajectory_file.h) and the one camera-file rule
// (loadCameraFile: calib.txt or camera_info YAML).
#include <dvs_calibration/camera_model.h>
#include <dvs_calibration/trajectory_accuracy.h>
#include <dvs_calibration/trajectory_file.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <functional>
#include <sstream>
#include <string>

using namespace dvs_calibration;

namespace
{
std::string tempPath(const std::string& name) { return ::testing::TempDir() + "/" + name; }

/// Ground truth at 1 kHz over [0, duration): a camera moving along x and turning about z.
Trajectory groundTruth(double duration_s = 1.0)
{
  Trajectory gt;
  for (int i = 0; i < static_cast<int>(std::lround(duration_s * 1000)); ++i)
  {
    const double t = i * 1e-3;
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.5 * t, Eigen::Vector3d::UnitZ()));
    gt.push_back({t, Pose::fromWorldCamera(q, Eigen::Vector3d(0.3 * t, 0.1, 2.0))});
  }
  return gt;
}

/// `gt` with every camera centre moved by `offset_world` (same orientation).
Trajectory shifted(const Trajectory& gt, const Eigen::Vector3d& offset_world)
{
  Trajectory est;
  for (const auto& g : gt)
    est.push_back({g.t, Pose::fromWorldCamera(g.T_world_camera.R_world_camera(),
                                              g.T_world_camera.p_world_camera() + offset_world)});
  return est;
}

std::string errorOf(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(TrajectoryAccuracy, ConstantOffsetOf1cmIsAnRmsOf1cm)
{
  const Trajectory gt = groundTruth();
  const AccuracyReport r = evaluateTrajectory(shifted(gt, Eigen::Vector3d(0.006, 0.0, 0.008)), gt);
  EXPECT_EQ(r.samples, 1000);
  EXPECT_EQ(r.samples_fresh, 1000);
  EXPECT_EQ(r.samples_tracked, 1000);
  EXPECT_NEAR(r.rms_position_m, 0.01, 1e-9);
  EXPECT_NEAR(r.max_position_m, 0.01, 1e-9);
  EXPECT_NEAR(r.mean_position_m, 0.01, 1e-9);
  EXPECT_NEAR(r.rms_orientation_rad, 0.0, 1e-6);
  EXPECT_DOUBLE_EQ(r.trackedFraction(), 1.0);
  EXPECT_DOUBLE_EQ(r.first_estimate_s, 0.0);
}

TEST(TrajectoryAccuracy, ConstantRotationOf2DegreesIsAnRmsOf2Degrees)
{
  const Trajectory gt = groundTruth();
  Trajectory est;
  const Eigen::Matrix3d dR = Eigen::AngleAxisd(2.0 * M_PI / 180, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (const auto& g : gt)
    est.push_back({g.t, Pose::fromWorldCamera(g.T_world_camera.R_world_camera() * dR, g.T_world_camera.p_world_camera())});
  const AccuracyReport r = evaluateTrajectory(est, gt);
  EXPECT_NEAR(r.rms_orientation_rad * 180 / M_PI, 2.0, 1e-6);
  EXPECT_NEAR(r.max_orientation_rad * 180 / M_PI, 2.0, 1e-6);
  EXPECT_NEAR(r.rms_position_m, 0.0, 1e-9);
  EXPECT_EQ(r.samples_tracked, r.samples);
}

TEST(TrajectoryAccuracy, FirstEstimateTimeAndSamplesFromItOn)
{
  const Trajectory gt = groundTruth();
  // Estimates from 0.25 s on: the samples before are not counted.
  Trajectory est;
  for (const auto& sp : gt)
    if (sp.t >= 0.25 - 1e-9)
      est.push_back(sp);
  const AccuracyReport r = evaluateTrajectory(est, gt);
  EXPECT_NEAR(r.first_estimate_s, 0.25, 1e-12);
  EXPECT_EQ(r.samples, 750);
  EXPECT_EQ(r.samples_tracked, 750);
  EXPECT_NEAR(r.rms_position_m, 0.0, 1e-12);
  // No estimate at all: nothing evaluated, first_estimate_s -1.
  const AccuracyReport none = evaluateTrajectory(Trajectory(), gt);
  EXPECT_EQ(none.samples, 0);
  EXPECT_EQ(none.first_estimate_s, -1);
  EXPECT_DOUBLE_EQ(none.trackedFraction(), 0.0);
}

TEST(TrajectoryAccuracy, StaleEstimateBeyondMaxAgeIsNotFresh)
{
  const Trajectory gt = groundTruth();
  // One exact estimate at 0.1 s and the next (and last) at 0.5 s: the samples in (0.15, 0.5)
  // and after 0.55 s have an estimate older than max_age (0.05 s): neither fresh nor tracked.
  Trajectory est = {gt[100], gt[500]};
  AccuracyOptions o;
  o.max_age_s = 0.0505;  // 0.05 s and a margin for the rounding of the sample times
  o.max_position_m = 1.0;  // the held pose is within the error bounds: only its age counts
  o.max_orientation_rad = 1.0;
  const AccuracyReport r = evaluateTrajectory(est, gt, o);
  EXPECT_EQ(r.samples, 900);        // 0.100 .. 0.999 s
  EXPECT_EQ(r.samples_fresh, 102);  // 0.100 .. 0.150 s (51) and 0.500 .. 0.550 s (51)
  EXPECT_EQ(r.samples_tracked, r.samples_fresh);
  EXPECT_NEAR(r.trackedFraction(), 102.0 / 900.0, 1e-12);
  // A generous max_age makes every sample fresh.
  o.max_age_s = 1.0;
  EXPECT_EQ(evaluateTrajectory(est, gt, o).samples_fresh, 900);
}

TEST(TrajectoryAccuracy, ErrorOver10cmIsNotTracked)
{
  const Trajectory gt = groundTruth();
  // 11 cm off during the second half, exact during the first.
  Trajectory est = gt;
  const Trajectory off = shifted(gt, Eigen::Vector3d(0, 0.11, 0));
  for (size_t i = 500; i < est.size(); ++i)
    est[i] = off[i];
  const AccuracyReport r = evaluateTrajectory(est, gt);
  EXPECT_EQ(r.samples, 1000);
  EXPECT_EQ(r.samples_fresh, 1000);
  EXPECT_EQ(r.samples_tracked, 500);
  EXPECT_NEAR(r.max_position_m, 0.11, 1e-9);
  EXPECT_NEAR(r.rms_position_m, 0.11 * std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(r.mean_position_m, 0.055, 1e-9);
  // Within 12 cm it is tracked.
  AccuracyOptions o;
  o.max_position_m = 0.12;
  EXPECT_EQ(evaluateTrajectory(est, gt, o).samples_tracked, 1000);
}

TEST(TrajectoryAccuracy, FromAndToLimitTheSamples)
{
  const Trajectory gt = groundTruth();
  AccuracyOptions o;
  o.from_s = 0.1995;
  o.to_s = 0.3005;
  const AccuracyReport r = evaluateTrajectory(gt, gt, o);
  EXPECT_EQ(r.samples, 101);  // 0.200 .. 0.300 s
}

TEST(TrajectoryAccuracy, JsonHasEveryFigureInMetresAndDegrees)
{
  const Trajectory gt = groundTruth();
  const std::string json = evaluateTrajectory(shifted(gt, Eigen::Vector3d(0.01, 0, 0)), gt).json();
  for (const char* key : {"\"samples\": 1000", "\"samples_fresh\": 1000", "\"samples_tracked\": 1000",
                          "\"tracked_fraction\": 1.000000", "\"rms_position_m\": 0.010000", "\"max_position_m\": 0.010000",
                          "\"rms_orientation_deg\": 0.000000", "\"first_estimate_s\": 0.000000"})
    EXPECT_NE(json.find(key), std::string::npos) << key << " in " << json;
  EXPECT_EQ(json.front(), '{');
  EXPECT_EQ(json.back(), '}');
}

TEST(TrajectoryFile, WriteReadRoundTrip)
{
  const Trajectory gt = groundTruth(0.2);
  const std::string path = tempPath("round_trip.tum");
  writeTumTrajectory(path, gt, "t tx ty tz qx qy qz qw");
  const Trajectory back = readTumTrajectory(path);
  ASSERT_EQ(back.size(), gt.size());
  for (size_t i = 0; i < gt.size(); ++i)
  {
    EXPECT_NEAR(back[i].t, gt[i].t, 1e-9);
    EXPECT_LT(positionError(back[i].T_world_camera, gt[i].T_world_camera), 1e-8);
    EXPECT_LT(orientationError(back[i].T_world_camera, gt[i].T_world_camera), 1e-8);
  }
  std::remove(path.c_str());
}

TEST(TrajectoryFile, NumbersAreWrittenAsPrintfWritesThem)
{
  // appendFixed stands for printf("%.*f") in every trajectory writer: the same characters for
  // random values of every magnitude, exact binary ties (round half to even), signed zeros and
  // values beyond 1e300; appendSeconds for "%s%llu.%09llu" of a signed nanosecond count.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-12, 12), decimals(0, 17);
  std::vector<double> values = {0.0, -0.0, 0.5, 1.5, 2.5, -2.5, 0.125, 0.375, 1e300, -1.7976931348623157e308,
                                std::numeric_limits<double>::denorm_min(), 123456789.123456789,
                                std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (int i = 0; i < 20000; ++i)
    values.push_back(mantissa(rng) * std::pow(10.0, exponent(rng)));
  int differing = 0;
  for (size_t i = 0; i < values.size(); ++i)
    for (const int d : {i < 14 ? 0 : decimals(rng), 6, 7, 9})
    {
      std::string ours;
      appendFixed(ours, values[i], d);
      std::vector<char> theirs(1024);
      std::snprintf(theirs.data(), theirs.size(), "%.*f", d, values[i]);
      if (ours != theirs.data() && ++differing <= 5)
        ADD_FAILURE() << values[i] << " with " << d << " decimals: " << ours << " instead of " << theirs.data();
    }
  EXPECT_EQ(differing, 0);
  std::string nan;
  appendFixed(nan, std::numeric_limits<double>::quiet_NaN(), 6);
  EXPECT_EQ(nan, "nan");

  std::uniform_int_distribution<int64_t> ns(std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max());
  std::vector<int64_t> times = {0, 1, -1, 999999999, 1000000000, -1000000000, 12000000345,
                                std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max()};
  for (int i = 0; i < 2000; ++i)
    times.push_back(i % 2 ? ns(rng) : ns(rng) % 100000000000LL);
  for (const int64_t t : times)
  {
    std::string ours;
    appendSeconds(ours, t);
    const bool negative = t < 0;
    const uint64_t a = negative ? static_cast<uint64_t>(-(t + 1)) + 1 : static_cast<uint64_t>(t);
    char theirs[64];
    std::snprintf(theirs, sizeof(theirs), "%s%llu.%09llu", negative ? "-" : "",
                  static_cast<unsigned long long>(a / 1000000000ULL), static_cast<unsigned long long>(a % 1000000000ULL));
    EXPECT_EQ(ours, theirs) << t;
  }
  std::string s;
  appendSeconds(s, -1);
  EXPECT_EQ(s, "-0.000000001");
}

TEST(TrajectoryFile, MalformedLinesNameFileAndLine)
{
  const std::string path = tempPath("malformed.tum");
  {
    std::ofstream(path) << "# header\n0.0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 1\n";
  }
  const std::string seven = errorOf([&] { readTumTrajectory(path); });
  EXPECT_NE(seven.find(path + ":3:"), std::string::npos) << seven;
  EXPECT_NE(seven.find("expected 8 values"), std::string::npos) << seven;
  {
    std::ofstream(path) << "0.0 0 0 0 0 0 0 1\n0.1 0 abc 0 0 0 0 1\n";
  }
  const std::string nan = errorOf([&] { readTumTrajectory(path); });
  EXPECT_NE(nan.find(path + ":2:"), std::string::npos) << nan;
  {
    std::ofstream(path) << "0.2 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n";
  }
  const std::string back = errorOf([&] { readTumTrajectory(path); });
  EXPECT_NE(back.find(path + ":2:"), std::string::npos) << back;
  {
    std::ofstream(path) << "0.0 0 0 0 0 0 0 1\n0.0 0 0 0 0 0 0 1\n";
  }
  EXPECT_THROW(readTumTrajectory(path), TrajectoryFileError);  // a repeated time: not for ground truth
  EXPECT_EQ(readTumTrajectory(path, TimeOrder::NonDecreasing).size(), 2u);  // but for an estimate
  const std::string missing = errorOf([&] { readTumTrajectory(tempPath("no_such_trajectory.tum")); });
  EXPECT_NE(missing.find("no_such_trajectory.tum"), std::string::npos) << missing;
  std::remove(path.c_str());
}

TEST(CameraFile, YamlCalibTxtAndTheirSizes)
{
  const std::string yaml = tempPath("camera_file.yaml"), txt = tempPath("camera_file_calib.txt");
  saveCameraInfoYaml(yaml, CameraModel::davis240(), "davis");
  saveCalibTxt(txt, CameraModel::davis240());
  // YAML: the size is in the file; a matching size (or none) is fine.
  EXPECT_EQ(loadCameraFile(yaml).width(), 240);
  EXPECT_EQ(loadCameraFile(yaml, 240, 180).height(), 180);
  std::string name;
  loadCameraFile(yaml, 0, 0, &name);
  EXPECT_EQ(name, "davis");
  // ... a different size is an error naming the file and both sizes.
  const std::string mismatch = errorOf([&] { loadCameraFile(yaml, 128, 128); });
  EXPECT_NE(mismatch.find(yaml), std::string::npos) << mismatch;
  EXPECT_NE(mismatch.find("240x180"), std::string::npos) << mismatch;
  EXPECT_NE(mismatch.find("128x128"), std::string::npos) << mismatch;
  EXPECT_THROW(loadCameraFile(yaml, 128, 128), CameraModelError);
  // calib.txt: no size in the file, so it must be given.
  const CameraModel cam = loadCameraFile(txt, 240, 180);
  EXPECT_EQ(cam.width(), 240);
  EXPECT_TRUE(cam.cameraMatrix().isApprox(CameraModel::davis240().cameraMatrix(), 1e-9));
  const std::string no_size = errorOf([&] { loadCameraFile(txt); });
  EXPECT_NE(no_size.find(txt), std::string::npos) << no_size;
  EXPECT_NE(no_size.find("width and height"), std::string::npos) << no_size;
  EXPECT_THROW(loadCameraFile(txt, 240, 0), CameraModelError);
  EXPECT_TRUE(isCameraInfoYamlPath("a/b.yml"));
  EXPECT_FALSE(isCameraInfoYamlPath("calib.txt"));
  std::remove(yaml.c_str());
  std::remove(txt.c_str());
}

TEST(TrajectoryFile, WrittenQuaternionsAreContinuous)
{
  // A full turn about z sampled every 10 deg: the rotation matrix -> quaternion conversion may
  // pick either sign; the file keeps neighbouring quaternions in the same hemisphere.
  Trajectory poses;
  for (int i = 0; i <= 72; ++i)
  {
    const double a = i * 10.0 * M_PI / 180.0;
    poses.push_back({0.01 * i, Pose::fromWorldCamera(Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ())),
                                                     Eigen::Vector3d::Zero())});
  }
  std::stringstream ss;
  writeTumTrajectory(ss, poses);
  const Trajectory back = readTumTrajectory(ss, "turn");
  ASSERT_EQ(back.size(), poses.size());
  std::stringstream again;
  writeTumTrajectory(again, poses);
  std::string line;
  double last[4] = {0, 0, 0, 1};
  int rows = 0;
  while (std::getline(again, line))
  {
    double t, x, y, z, qx, qy, qz, qw;
    if (std::sscanf(line.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf", &t, &x, &y, &z, &qx, &qy, &qz, &qw) != 8)
      continue;
    EXPECT_GT(qx * last[0] + qy * last[1] + qz * last[2] + qw * last[3], 0.9) << "row " << rows;
    last[0] = qx, last[1] = qy, last[2] = qz, last[3] = qw;
    ++rows;
  }
  EXPECT_EQ(rows, 73);
  for (size_t i = 0; i < back.size(); ++i)
    EXPECT_LT(orientationError(back[i].T_world_camera, poses[i].T_world_camera), 1e-6);  // 9 decimals
}
