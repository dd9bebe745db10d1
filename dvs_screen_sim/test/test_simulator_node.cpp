// rostest: the simulator (node or nodelet) publishes events inside the sensor, ground truth,
// camera_info, the map and the IMU (dvs/imu at 1 kHz of simulated time, frame dvs).
#include <dvs_msgs/EventArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cmath>
#include <cstdlib>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Imu.h>
#include <visualization_msgs/MarkerArray.h>

namespace
{
size_t g_events = 0, g_packets = 0, g_outside = 0, g_poses = 0, g_infos = 0, g_maps = 0;
bool g_backwards = false;
int64_t g_last_ns = 0;
uint32_t g_width = 0;
size_t g_imu = 0, g_imu_steps = 0, g_imu_bad_frame = 0, g_imu_bad_gravity = 0;
int64_t g_last_imu_ns = 0;
}  // namespace

TEST(SimulatorNode, PublishesEventsAndGroundTruth)
{
  ros::NodeHandle nh;
  auto ev_sub = nh.subscribe<dvs_msgs::EventArray>("dvs/events", 1000, boost::function<void(const dvs_msgs::EventArray::ConstPtr&)>([](const dvs_msgs::EventArray::ConstPtr& m) {
    ++g_packets;
    g_width = m->width;
    for (const auto& e : m->events)
    {
      ++g_events;
      if (e.x >= m->width || e.y >= m->height)
        ++g_outside;
      const int64_t ns = static_cast<int64_t>(e.ts.sec) * 1000000000LL + e.ts.nsec;
      if (ns < g_last_ns)
        g_backwards = true;
      g_last_ns = ns;
    }
  }));
  auto pose_sub = nh.subscribe<geometry_msgs::PoseStamped>(
      "dvs/ground_truth/pose", 1000, boost::function<void(const geometry_msgs::PoseStamped::ConstPtr&)>([](const geometry_msgs::PoseStamped::ConstPtr& p) {
        ++g_poses;
        EXPECT_EQ(p->header.frame_id, "world");
        EXPECT_GT(p->pose.position.z, 0.5);  // in front of the wall
      }));
  auto info_sub = nh.subscribe<sensor_msgs::CameraInfo>("dvs/camera_info", 10,
                                                        boost::function<void(const sensor_msgs::CameraInfo::ConstPtr&)>([](const sensor_msgs::CameraInfo::ConstPtr&) { ++g_infos; }));
  auto map_sub = nh.subscribe<visualization_msgs::MarkerArray>(
      "dvs/ground_truth/map", 1, boost::function<void(const visualization_msgs::MarkerArray::ConstPtr&)>([](const visualization_msgs::MarkerArray::ConstPtr& m) {
        ++g_maps;
        ASSERT_FALSE(m->markers.empty());
        EXPECT_EQ(m->markers[0].points.size(), 8u);  // 4 edges of the square
      }));
  auto imu_sub = nh.subscribe<sensor_msgs::Imu>(
      "dvs/imu", 1000, boost::function<void(const sensor_msgs::Imu::ConstPtr&)>([](const sensor_msgs::Imu::ConstPtr& m) {
        const int64_t ns = static_cast<int64_t>(m->header.stamp.sec) * 1000000000LL + m->header.stamp.nsec;
        // Consecutive samples 1 ms apart (a new run of the loop restarts the time base).
        if (g_imu > 0 && ns > g_last_imu_ns)
          g_imu_steps += std::llabs(ns - g_last_imu_ns - 1000000) < 1000;
        g_last_imu_ns = ns;
        ++g_imu;
        g_imu_bad_frame += m->header.frame_id != "dvs";
        const double f = std::sqrt(m->linear_acceleration.x * m->linear_acceleration.x +
                                   m->linear_acceleration.y * m->linear_acceleration.y +
                                   m->linear_acceleration.z * m->linear_acceleration.z);
        g_imu_bad_gravity += f < 5.0 || f > 60.0;  // gravity plus the flip's accelerations
      }));
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && ros::WallTime::now() < deadline &&
         (g_events < 5000 || g_poses < 200 || !g_infos || !g_maps || g_imu < 300))
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  EXPECT_GE(g_events, 5000u);
  EXPECT_GE(g_poses, 200u);
  EXPECT_GE(g_infos, 1u);
  EXPECT_GE(g_maps, 1u);
  EXPECT_EQ(g_outside, 0u);
  EXPECT_FALSE(g_backwards);
  EXPECT_EQ(g_width, 128u);
  // dvs/imu: as many samples as ground-truth poses (both 1 kHz of simulated time), 1 ms apart.
  EXPECT_GE(g_imu, 300u);
  EXPECT_GE(g_imu_steps, g_imu * 9 / 10);
  EXPECT_EQ(g_imu_bad_frame, 0u);
  EXPECT_EQ(g_imu_bad_gravity, 0u);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_simulator_node");
  ros::NodeHandle keep_alive;  // the node lives until the tests are over
  const int result = RUN_ALL_TESTS();
  ros::shutdown();
  return result;
}
