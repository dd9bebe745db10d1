#include <dvs_driver/event_bag_io.h>
#include <dvs_screen_sim/bag_output.h>
#include <gtest/gtest.h>
#include <geometry_msgs/PoseStamped.h>
#include <dvs_driver/imu_msg.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <filesystem>

using namespace dvs_screen_sim;

TEST(BagOutput, BagAndTextOutputsAgree)
{
  const SimConfig c = resolveSimConfig("flip", YAML::Load("{trajectory: {flip: {first_flip_time: 0.1}}}"), 3, 0.2);
  const SimulationOutput out = runSimulation(c);
  const std::string path =
      (std::filesystem::temp_directory_path() / ("dvs_screen_sim_bag_" + std::to_string(::getpid()) + ".bag")).string();
  writeSimulationBag(path, c, out);
  const dvs_driver::EventStream stream = dvs_driver::readEventsBag(path, "/dvs/events");
  EXPECT_EQ(stream.width, 128u);
  EXPECT_EQ(stream.height, 128u);
  ASSERT_GT(out.events.size(), 1000u);
  EXPECT_EQ(stream.events, out.events);

  rosbag::Bag bag(path, rosbag::bagmode::Read);
  size_t poses = 0, tf = 0, info = 0, map = 0, packets = 0, imu = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag))
  {
    if (m.getTopic() == "/dvs/ground_truth/pose")
    {
      const auto p = m.instantiate<geometry_msgs::PoseStamped>();
      ASSERT_TRUE(p != nullptr);
      const auto& gt = out.groundtruth[poses];
      EXPECT_NEAR(p->header.stamp.toSec(), gt.t, 1e-9);
      EXPECT_NEAR(p->pose.position.z, gt.T_world_camera.p_world_camera().z(), 1e-12);
      ++poses;
    }
    if (m.getTopic() == "/dvs/imu")
    {
      // The IMU samples as sensor_msgs/Imu: same stamps and values, frame dvs, covariances
      // from the noise densities (per-sample sigma^2), no orientation.
      const auto p = m.instantiate<sensor_msgs::Imu>();
      ASSERT_TRUE(p != nullptr);
      ASSERT_LT(imu, out.imu.size());
      dvs_driver::ImuSample expected = out.imu[imu];
      expected.temperature_c = NAN;
      EXPECT_EQ(dvs_driver::fromImuMessage(*p), expected);
      EXPECT_EQ(p->header.frame_id, "dvs");
      EXPECT_DOUBLE_EQ(p->angular_velocity_covariance[0], 1.7e-4 * 1.7e-4 * 1000);
      EXPECT_DOUBLE_EQ(p->linear_acceleration_covariance[8], 2e-3 * 2e-3 * 1000);
      EXPECT_EQ(p->linear_acceleration_covariance[1], 0.0);
      EXPECT_EQ(p->orientation_covariance[0], -1.0);
      ++imu;
    }
    tf += m.getTopic() == "/tf";
    info += m.getTopic() == "/dvs/camera_info";
    map += m.getTopic() == "/dvs/ground_truth/map";
    packets += m.getTopic() == "/dvs/events";
  }
  EXPECT_EQ(poses, out.groundtruth.size());
  EXPECT_EQ(tf, out.groundtruth.size());
  EXPECT_EQ(imu, 201u);  // 1 kHz over 0.2 s
  EXPECT_EQ(imu, out.imu.size());
  EXPECT_EQ(info, 3u);  // 0, 0.1, 0.2 s
  EXPECT_EQ(map, 1u);
  EXPECT_GE(packets, 150u);  // 1 ms packets over 0.2 s, a few may be empty
  EXPECT_LE(packets, 201u);
  bag.close();
  std::filesystem::remove(path);
}
