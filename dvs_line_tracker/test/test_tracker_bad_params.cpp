// rostest: tracker_node with a bad parameter, a missing calibration file or a garbage map
// prints the reason and exits 1 (it used to exit 1 with no output at all); a misspelt parameter
// name is warned about (the YAML path refuses it, the ROS path used to ignore it silently).
#include <gtest/gtest.h>
#include <dvs_driver/testing/node_test_support.h>
#include <dvs_line_tracker/tracker_ros.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include <array>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace
{
// Runs tracker_node (its own process) with `args`, stdout and stderr captured.
dvs_driver::testing::ProcessRun runNode(const std::string& args)
{
  return dvs_driver::testing::runProcess(std::string(TRACKER_NODE) + " " + args);
}
}  // namespace

TEST(TrackerBadParams, OutOfRangeParameterIsPrintedNamingIt)
{
  const auto r = runNode("__name:=bad_tracker_buffer _buffer_size:=1");
  EXPECT_EQ(1, r.status) << r.output;
  EXPECT_NE(std::string::npos, r.output.find("buffer_size must be in [2, 1024] events (got 1)")) << r.output;
}

TEST(TrackerBadParams, MissingCalibrationFileIsPrinted)
{
  const auto r = runNode("__name:=bad_tracker_calib _calibration_file:=/nonexistent/calib.txt");
  EXPECT_EQ(1, r.status) << r.output;
  EXPECT_NE(std::string::npos, r.output.find("/nonexistent/calib.txt")) << r.output;
}

TEST(TrackerBadParams, GarbageMapIsPrinted)
{
  const std::string map = "/tmp/tracker_bad_map_" + std::to_string(::getpid()) + ".yaml";
  std::ofstream(map) << "segments: [[[0,0,0],[1,0]]]\n";
  const auto r = runNode("__name:=bad_tracker_map _map_file:=" + map);
  EXPECT_EQ(1, r.status) << r.output;
  EXPECT_NE(std::string::npos, r.output.find(map)) << r.output;
  std::remove(map.c_str());
}

TEST(TrackerBadParams, MisspeltNameIsWarnedAbout)
{
  ros::NodeHandle nh;
  dvs_driver::testing::RosoutLog log(nh);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  ros::param::set("/misspelt_tracker/bufer_size", 12);
  dvs_line_tracker::TrackerRos tracker(ros::NodeHandle(), ros::NodeHandle("/misspelt_tracker"));
  EXPECT_TRUE(log.waitFor("unknown parameter /misspelt_tracker/bufer_size ignored", 30));
}

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_tracker_bad_params");
  return RUN_ALL_TESTS();
}
