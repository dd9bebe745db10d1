// rostest: a bad parameter stops the driver with an error naming it, from the node (printed,
// exit status 1) and from the nodelet (logged, loading fails); an unknown name is warned about;
// a recording with bad events (duplicated lines) is replayed with its counters in the driver's
// diagnostics at WARN and a warning in the log.
#include <gtest/gtest.h>
#include <dvs_driver/testing/node_test_support.h>
#include <nodelet/loader.h>
#include <ros/ros.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <rosgraph_msgs/Log.h>

#include <fstream>
#include <unistd.h>

#include <array>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <string>
#include <sys/wait.h>

namespace
{
// Runs dvs_driver_node (the executable itself, no nodelet manager) with `args`, output captured.
dvs_driver::testing::ProcessRun runNode(const std::string& args)
{
  return dvs_driver::testing::runProcess(std::string(DRIVER_NODE) + " " + args);
}

bool loadNodelet(nodelet::Loader& loader, const std::string& name)
{
  try
  {
    return loader.load(name, "dvs_driver/DriverNodelet", nodelet::M_string(), nodelet::V_string());
  }
  catch (const std::exception&)
  {
    return false;
  }
}
}  // namespace

TEST(DriverBadParams, NodePrintsTheOutOfRangeParameterAndExits)
{
  const auto r = runNode("__name:=bad_node_period _packet_period:=5.0");
  EXPECT_EQ(1, r.status) << r.output;
  EXPECT_NE(std::string::npos, r.output.find("packet_period must be in [1e-05, 1] s (got 5)")) << r.output;
}

TEST(DriverBadParams, NodePrintsAnUnreadableFile)
{
  const auto r = runNode("__name:=bad_node_file _file:=/nonexistent/rec.aedat");
  EXPECT_EQ(1, r.status) << r.output;
  EXPECT_NE(std::string::npos, r.output.find("parameter ~file: /nonexistent/rec.aedat: cannot open")) << r.output;
}

TEST(DriverBadParams, NodeletLogsTheOutOfRangeParameterAndFailsToLoad)
{
  ros::NodeHandle nh;
  dvs_driver::testing::RosoutLog log(nh);
  ros::param::set("/bad_nodelet/transfers", 65);
  nodelet::Loader loader(false);
  EXPECT_FALSE(loadNodelet(loader, "/bad_nodelet"));
  EXPECT_TRUE(log.waitFor("transfers must be in [1, 64] (got 65)"));
}

TEST(DriverBadParams, UnknownNameIsWarnedAboutAndDeprecatedAliasRead)
{
  ros::NodeHandle nh;
  dvs_driver::testing::RosoutLog log(nh);
  ros::param::set("/typo_nodelet/file", std::string(DVS_REAL_DATA_DIR "/ucsd_alex_walking_again.aedat"));
  ros::param::set("/typo_nodelet/wait_for_subscriber", true);
  ros::param::set("/typo_nodelet/replay_sped", 2.0);
  ros::param::set("/typo_nodelet/packet_period_ms", 5.0);
  nodelet::Loader loader(false);
  ASSERT_TRUE(loadNodelet(loader, "/typo_nodelet"));
  EXPECT_TRUE(log.waitFor("unknown parameter /typo_nodelet/replay_sped ignored"));
  EXPECT_TRUE(log.waitFor("packet_period_ms is deprecated: set ~packet_period: 0.005 (seconds) instead"));
  double period = 0;
  EXPECT_TRUE(ros::param::get("/typo_nodelet/packet_period", period));  // what dynamic_reconfigure serves
  EXPECT_DOUBLE_EQ(0.005, period);
  loader.unload("/typo_nodelet");
}

TEST(DriverBadInput, ReplayCountersInDiagnosticsAtWarnAndALoggedWarning)
{
  const std::string path = "/tmp/dvs_driver_bad_input_" + std::to_string(::getpid()) + ".txt";
  {
    std::ofstream out(path);
    for (int i = 0; i < 300; ++i)
      for (int k = 0; k < 2; ++k)  // every line twice
        out << "1." << (100000 + i) << " " << (i % 100) << " 7 1\n";
  }
  std::mutex m;
  std::condition_variable cv;
  diagnostic_msgs::DiagnosticStatus found;
  bool have = false;
  ros::NodeHandle nh;
  dvs_driver::testing::RosoutLog log(nh);
  ros::Subscriber diag_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 100, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& a) {
        for (const auto& st : a->status)
          if (st.name.find("DVS event stream") != std::string::npos && st.message.find("end of file") == 0)
          {
            std::lock_guard<std::mutex> lock(m);
            found = st;
            have = true;
            cv.notify_all();
          }
      });
  ros::param::set("/bad_input_nodelet/file", path);
  ros::param::set("/bad_input_nodelet/replay_speed", 0.0);
  nodelet::Loader loader(false);
  ASSERT_TRUE(loadNodelet(loader, "/bad_input_nodelet"));
  {
    std::unique_lock<std::mutex> lock(m);
    ASSERT_TRUE(cv.wait_for(lock, std::chrono::seconds(30), [&] { return have; }));
  }
  EXPECT_EQ(diagnostic_msgs::DiagnosticStatus::WARN, found.level);
  EXPECT_NE(std::string::npos, found.message.find("input problems: 300 exact duplicates (50% of 600 events)"))
      << found.message;
  bool counter = false;
  for (const auto& kv : found.values)
    if (kv.key == "exact duplicate events")
    {
      counter = true;
      EXPECT_EQ("300", kv.value);
    }
  EXPECT_TRUE(counter);
  EXPECT_TRUE(log.waitFor(path + ": 300 exact duplicates (50% of 600 events)"));
  loader.unload("/bad_input_nodelet");
  std::remove(path.c_str());
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_driver_bad_params");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
