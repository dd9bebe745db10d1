// The screen_loop node end to end: with a software DVS filming the X screen (fake_screen_dvs),
// the node must align (ground truth is only published after a successful alignment) and then
// publish the ground truth of the playback.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

TEST(ScreenLoopNode, AlignsOnTheFilmedScreenAndPublishesGroundTruth)
{
  ros::NodeHandle nh;
  std::vector<geometry_msgs::PoseStamped> poses;
  ros::Subscriber sub = nh.subscribe<geometry_msgs::PoseStamped>(
      "dvs/ground_truth/pose", 1000, [&](const geometry_msgs::PoseStamped::ConstPtr& m) { poses.push_back(*m); });
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(90.0);
  while (ros::ok() && poses.size() < 20 && ros::WallTime::now() < deadline)
  {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_GE(poses.size(), 20u) << "no ground truth: the alignment on the filmed screen failed or timed out";
  EXPECT_EQ(poses.front().header.frame_id, "world");
  // The flip hovers 2 m in front of the wall.
  EXPECT_NEAR(poses.front().pose.position.z, 2.0, 0.1);
  for (size_t i = 1; i < poses.size(); ++i)
    EXPECT_GE(poses[i].header.stamp.toSec(), poses[i - 1].header.stamp.toSec());
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_screen_loop_node");
  return RUN_ALL_TESTS();
}
