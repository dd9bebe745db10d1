#include <dvs_screen_sim/trajectory.h>
#include <dvs_calibration/trajectory_file.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

using namespace dvs_screen_sim;
// The TUM reader and writer are dvs_calibration's (the suite's one home for trajectory files);
// these tests pin down what the simulator's ground truth and file playback rely on.
using dvs_calibration::readTumTrajectory;
using dvs_calibration::TimeOrder;
using dvs_calibration::TrajectoryFileError;
using dvs_calibration::writeTumTrajectory;

namespace
{
double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b)
{
  return a.angularDistance(b);
}
}  // namespace

TEST(TrajectoryIo, RoundTripIsExactTo1e9)
{
  dvs_calibration::Trajectory poses;
  for (int i = 0; i < 20; ++i)
  {
    const Pose p = Pose::fromWorldCamera(Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(1, 2, 3).normalized())), Eigen::Vector3d(0.1 * i, -0.2 * i, 1.5 + 0.01 * i));
    poses.push_back({0.001 * i + 5.0, p});
  }
  std::stringstream ss;
  writeTumTrajectory(ss, poses, "test");
  const dvs_calibration::Trajectory back = readTumTrajectory(ss, "mem");
  ASSERT_EQ(back.size(), poses.size());
  for (size_t i = 0; i < poses.size(); ++i)
  {
    EXPECT_NEAR(back[i].t, poses[i].t, 1e-9);
    EXPECT_LT((back[i].T_world_camera.p_world_camera() - poses[i].T_world_camera.p_world_camera()).norm(), 2e-9);
    EXPECT_LT(angleBetween(back[i].T_world_camera.q_world_camera(), poses[i].T_world_camera.q_world_camera()), 1e-8);
  }
}

TEST(TrajectoryIo, ReadsCsvWithHeader)
{
  std::stringstream ss("t,px,py,pz,qx,qy,qz,qw\n0,1,2,3,0,0,0,1\n0.5,1,2,3,0,0,0,1.2\n");
  const dvs_calibration::Trajectory poses = readTumTrajectory(ss, "mem.csv");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_DOUBLE_EQ(poses[1].t, 0.5);
  EXPECT_DOUBLE_EQ(poses[1].T_world_camera.q_world_camera().w(), 1.0);  // normalised
}

TEST(TrajectoryIo, RejectsMalformedLinesNamingTheLine)
{
  std::stringstream few("# c\n0 1 2 3 0 0 0\n");
  try
  {
    readTumTrajectory(few, "few.txt");
    FAIL() << "no exception";
  }
  catch (const TrajectoryFileError& e)
  {
    EXPECT_NE(std::string(e.what()).find("few.txt:2"), std::string::npos) << e.what();
  }
  std::stringstream back("1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n");
  EXPECT_THROW(readTumTrajectory(back, "b"), TrajectoryFileError);
  std::stringstream repeat("1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n");
  EXPECT_THROW(readTumTrajectory(repeat, "r"), TrajectoryFileError);  // ground truth must increase
  std::stringstream word("1 0 0 zero 0 0 0 1\n");
  EXPECT_THROW(readTumTrajectory(word, "w"), TrajectoryFileError);
  std::stringstream zeroq("1 0 0 0 0 0 0 0\n");
  EXPECT_THROW(readTumTrajectory(zeroq, "q"), TrajectoryFileError);
  EXPECT_THROW(readTumTrajectory("/nonexistent/traj.txt"), TrajectoryFileError);
}

TEST(TrajectoryIo, EstimatesMayRepeatATimeButNotGoBack)
{
  std::stringstream repeat("1 0 0 0 0 0 0 1\n1 0.1 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n");
  const dvs_calibration::Trajectory poses = readTumTrajectory(repeat, "est.txt", TimeOrder::NonDecreasing);
  ASSERT_EQ(3u, poses.size());
  EXPECT_DOUBLE_EQ(0.1, poses[1].T_world_camera.p_world_camera().x());
  std::stringstream back("1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n");
  EXPECT_THROW(readTumTrajectory(back, "est.txt", TimeOrder::NonDecreasing), TrajectoryFileError);
}

TEST(HelixTrajectory, OpticalAxisThroughSquareCentreAtGrowingDistance)
{
  HelixTrajectoryParams p;  // thesis: 2 turns, tilt 30 deg, 4 s
  const HelixTrajectory helix(p);
  for (double t = 0; t <= 4.0; t += 0.37)
  {
    const Pose pose = helix.poseAt(t);
    const double d = p.start_distance + (p.end_distance - p.start_distance) * t / p.duration;
    EXPECT_NEAR(pose.p_world_camera().norm(), d, 1e-9);
    // The wall origin is on the optical axis, in front of the camera at depth d.
    const Eigen::Vector3d origin_cam = pose.toCamera(Eigen::Vector3d::Zero());
    EXPECT_NEAR(origin_cam.x(), 0, 1e-9);
    EXPECT_NEAR(origin_cam.y(), 0, 1e-9);
    EXPECT_NEAR(origin_cam.z(), d, 1e-9);
    // Camera in front of the wall, optical axis 30 deg off the wall normal.
    EXPECT_GT(pose.p_world_camera().z(), 0);
    const Eigen::Vector3d axis = pose.q_world_camera() * Eigen::Vector3d::UnitZ();
    EXPECT_NEAR(std::acos(-axis.z()) * 180 / M_PI, 30.0, 1e-6);
  }
  // Two full turns: the azimuth of the camera centre returns to its start.
  EXPECT_LT((helix.poseAt(4.0).p_world_camera().normalized() - helix.poseAt(0.0).p_world_camera().normalized()).norm(), 1e-9);
  EXPECT_GT((helix.poseAt(1.0).p_world_camera().normalized() - helix.poseAt(0.0).p_world_camera().normalized()).norm(), 0.5);
  // At the start the image's up is world +y (the map's up).
  const Eigen::Vector3d image_up = helix.poseAt(0).q_world_camera() * Eigen::Vector3d(0, -1, 0);
  EXPECT_GT(image_up.y(), 0.8);
}

TEST(FlipTrajectory, OneFullRollWithThePeakRate)
{
  FlipTrajectoryParams p;
  p.sway = 0;
  const FlipTrajectory flip(p);
  EXPECT_NEAR(flip.rollAt(0), 0, 1e-8);
  EXPECT_NEAR(flip.rollAt(flip.naturalDuration()), 2 * M_PI, 1e-6);
  const double tc = p.first_flip_time;
  EXPECT_NEAR(flip.rollRateAt(tc) * 180 / M_PI, 1200.0, 1e-9);
  // Rate from the poses (finite differences) agrees, and the roll is about the optical axis.
  const double h = 1e-5;
  const Eigen::Quaterniond q0 = flip.poseAt(tc - h).q_world_camera(), q1 = flip.poseAt(tc + h).q_world_camera();
  EXPECT_NEAR(q0.angularDistance(q1) / (2 * h) * 180 / M_PI, 1200.0, 0.5);
  const Eigen::Vector3d axis0 = q0 * Eigen::Vector3d::UnitZ(), axis1 = q1 * Eigen::Vector3d::UnitZ();
  EXPECT_LT((axis0 - axis1).norm(), 1e-9);
  EXPECT_NEAR(flip.poseAt(tc).p_world_camera().y(), p.rise, 1e-9);       // apex
  EXPECT_LT(std::abs(flip.poseAt(0).p_world_camera().y()), 0.1 * p.rise);  // hovering low before
  EXPECT_NEAR(flip.poseAt(tc).p_world_camera().z(), p.distance, 1e-9);
  // Bell-shaped: far from the flip the rate is negligible.
  EXPECT_LT(flip.rollRateAt(0.0), 1e-3);
}

TEST(LinearTrajectory, InterpolatesEndpoints)
{
  LinearTrajectoryParams p;
  const LinearTrajectory lin(p);
  EXPECT_LT((lin.poseAt(0).p_world_camera() - p.start_position).norm(), 1e-12);
  EXPECT_LT((lin.poseAt(p.duration).p_world_camera() - p.end_position).norm(), 1e-12);
  EXPECT_LT((lin.poseAt(p.duration / 2).p_world_camera() - 0.5 * (p.start_position + p.end_position)).norm(), 1e-12);
  EXPECT_LT(lin.poseAt(0).q_world_camera().angularDistance(orientationFromYawPitchRollDeg(p.start_ypr_deg)), 1e-12);
  // Roll is about the optical axis: pure roll keeps the optical axis.
  const Eigen::Vector3d a = orientationFromYawPitchRollDeg({0, 0, 40}) * Eigen::Vector3d::UnitZ();
  EXPECT_LT((a - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
}

TEST(RandomTrajectory, SeededAndSmooth)
{
  RandomTrajectoryParams p;
  const RandomTrajectory a(p, 7), b(p, 7), c(p, 8);
  EXPECT_LT((a.poseAt(0).p_world_camera() - Eigen::Vector3d(0, 0, p.distance)).norm(), 1e-12);
  EXPECT_EQ(a.poseAt(1.234).p_world_camera(), b.poseAt(1.234).p_world_camera());
  EXPECT_GT((a.poseAt(1.234).p_world_camera() - c.poseAt(1.234).p_world_camera()).norm(), 1e-6);
  for (double t = 0; t < 5; t += 0.1)
  {
    const Pose x = a.poseAt(t), y = a.poseAt(t + 1e-4);
    EXPECT_LT((x.p_world_camera() - y.p_world_camera()).norm(), 1e-3);
    EXPECT_LT(x.q_world_camera().angularDistance(y.q_world_camera()), 1e-3);
  }
}

TEST(SampledTrajectory, PassesThroughSamplesAndIsLinearExact)
{
  dvs_calibration::Trajectory poses;
  for (int i = 0; i < 10; ++i)
  {
    const Pose p = Pose::fromWorldCamera(Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * i, Eigen::Vector3d::UnitY())),
                                         Eigen::Vector3d(0.3 * i, 1.0, 2.0 - 0.1 * i));  // constant velocity
    poses.push_back({10.0 + 0.5 * i, p});
  }
  const SampledTrajectory traj(poses);
  EXPECT_DOUBLE_EQ(traj.naturalDuration(), 4.5);
  for (int i = 0; i < 10; ++i)
  {
    const Pose p = traj.poseAt(0.5 * i);
    EXPECT_LT((p.p_world_camera() - poses[i].T_world_camera.p_world_camera()).norm(), 1e-12);
    EXPECT_LT(p.q_world_camera().angularDistance(poses[i].T_world_camera.q_world_camera()), 1e-9);
  }
  // Constant velocity and constant rotation rate are reproduced between samples.
  const Pose mid = traj.poseAt(1.3);
  EXPECT_LT((mid.p_world_camera() - Eigen::Vector3d(0.3 * 2.6, 1.0, 2.0 - 0.26)).norm(), 1e-9);
  EXPECT_LT(mid.q_world_camera().angularDistance(Eigen::Quaterniond(Eigen::AngleAxisd(0.52, Eigen::Vector3d::UnitY()))), 1e-6);
  EXPECT_THROW(SampledTrajectory(dvs_calibration::Trajectory(1)), TrajectoryError);
}

TEST(SampleTrajectory, RateAndEndpoints)
{
  const StaticTrajectory s(Pose{});
  const dvs_calibration::Trajectory gt = sampleTrajectory(s, 0.5, 1000.0);
  ASSERT_EQ(gt.size(), 501u);
  EXPECT_DOUBLE_EQ(gt.back().t, 0.5);
  EXPECT_THROW(sampleTrajectory(s, 1.0, 0.0), TrajectoryError);
}
