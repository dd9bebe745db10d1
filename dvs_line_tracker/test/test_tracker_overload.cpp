// rostest: the tracker falls behind gracefully (issue 16). A simulated DAVIS346 sequence with two
// 1000 deg/s flips (about 0.7 M events/s of data) is published faster than real time, about twice
// what the tracker node can process on this machine: the latency from a packet's publication to
// the pose of its last event stays bounded (the tracker tracks every k-th event instead of
// queueing), the skipped events are reported in diagnostics, and the tracker keeps tracking.
#include <diagnostic_msgs/DiagnosticArray.h>
#include "camera_info_latch.h"
#include "diagnostic_value.h"
#include <dvs_driver/event_bag_io.h>
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/sim_config.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_msgs/String.h>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <map>
#include <mutex>

namespace
{
// The publishing speed: at least 3x real time (2.2 M events/s), and at least 1.2x the rate at
// which the tracker core processes this sequence offline on this machine (the node, with ROS
// around it, tracks at about 0.6x the core's rate: so about twice what the node can process,
// whatever the machine; a fixed 3x was twice the node's rate on a slow machine and none on a
// fast one). Far beyond that (5x on the slow machine) the tracker sometimes loses the track and
// its initialisation, far slower, stalls the queue for 1-2 s (BENCHMARKS.md); that is measured
// there, not asserted here.
constexpr double kMinSpeed = 3.0;
constexpr double kOverCoreRate = 1.2;

/// Events per second of wall time of the tracker core over the whole sequence.
double coreEventsPerSecond(const dvs_screen_sim::SimConfig& config, const dvs_driver::EventVector& events)
{
  dvs_line_tracker::LineTracker tracker(config.camera, dvs_line_tracker::defaultSquareMap());
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& e : events)
    tracker.processEvent(e);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return events.size() / std::max(1e-6, s);
}

}  // namespace

TEST(TrackerOverload, ThreeTimesRealTimeKeepsTheLatencyBounded)
{
  ros::NodeHandle nh;
  auto config = dvs_screen_sim::resolveSimConfig(
      "flip",
      YAML::Load("camera: {preset: davis346}\n"
                 "trajectory: {flip: {distance: 2.0, flips: 2, peak_rate_deg_s: 1000, first_flip_time: 0.75, "
                 "flip_interval: 1.2}}"),
      std::nullopt, 2.6);
  config.time_offset_ns = 1000000000LL;
  const auto sim = dvs_screen_sim::runSimulation(config);
  ASSERT_GT(sim.events.size(), 1000000u);

  std::mutex m;
  std::map<int64_t, ros::WallTime> published;  // last event stamp of a packet -> wall time published
  std::vector<double> lags_s;
  std::vector<geometry_msgs::PoseStamped> last_poses;  // the last pose of every batch
  std::vector<diagnostic_msgs::DiagnosticStatus> diagnostics;
  std::vector<std::string> states;
  auto poses_sub = nh.subscribe<nav_msgs::Path>("/dvs_line_tracker/poses", 100000, [&](const auto& msg) {
    const ros::WallTime now = ros::WallTime::now();
    std::lock_guard<std::mutex> l(m);
    // The batch's stamp is its last pose's event; the packet holding that event was published
    // at or before the first packet ending at or after it.
    const auto it = published.lower_bound(static_cast<int64_t>(msg->header.stamp.toNSec()));
    if (it != published.end())
      lags_s.push_back((now - it->second).toSec());
    if (!msg->poses.empty())
      last_poses.push_back(msg->poses.back());
  });
  auto diag_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 100, [&](const auto& msg) {
    std::lock_guard<std::mutex> l(m);
    for (const auto& s : msg->status)
      if (s.name.find("tracker") != std::string::npos)
        diagnostics.push_back(s);
  });
  auto state_sub = nh.subscribe<std_msgs::String>("/dvs_line_tracker/state", 100, [&](const auto& msg) {
    std::lock_guard<std::mutex> l(m);
    states.push_back(msg->data);
  });
  ros::AsyncSpinner spinner(2);
  spinner.start();

  const CameraInfoLatch info(nh, config.camera);
  ros::Publisher events_pub = nh.advertise<dvs_msgs::EventArray>("/dvs/events", 10000);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while ((events_pub.getNumSubscribers() == 0 || poses_sub.getNumPublishers() == 0 || !info.taken()) &&
         ros::WallTime::now() < deadline)
    ros::WallDuration(0.02).sleep();
  ASSERT_TRUE(info.taken()) << "the tracker did not take the camera_info within 30 s";

  const double data_rate = sim.events.size() / ((sim.events.back().t_ns - sim.events.front().t_ns) * 1e-9);
  const double core_rate = coreEventsPerSecond(config, sim.events);
  const double kSpeed = std::max(kMinSpeed, kOverCoreRate * core_rate / data_rate);
  std::printf("overload: the tracker core runs this sequence at %.2f M events/s offline; data %.2f M events/s; "
              "published at %.2fx real time\n",
              core_rate * 1e-6, data_rate * 1e-6, kSpeed);
  ::testing::Test::RecordProperty("speed_x_real_time", std::to_string(kSpeed));

  // 1 ms packets, each published when the wall clock reaches its last event at kSpeed.
  const int64_t t0 = sim.events.front().t_ns;
  const ros::WallTime wall0 = ros::WallTime::now();
  size_t i = 0;
  while (i < sim.events.size())
  {
    const int64_t period_end = (sim.events[i].t_ns / 1000000 + 1) * 1000000;
    size_t j = i;
    while (j < sim.events.size() && sim.events[j].t_ns < period_end)
      ++j;
    const auto packet = dvs_driver::toMessage(sim.events.data() + i, sim.events.data() + j, config.camera.width(),
                                              config.camera.height());
    const int64_t last_ns = sim.events[j - 1].t_ns;
    const ros::WallTime due = wall0 + ros::WallDuration((last_ns - t0) * 1e-9 / kSpeed);
    const ros::WallDuration wait = due - ros::WallTime::now();
    if (wait > ros::WallDuration(0))
      wait.sleep();
    {
      std::lock_guard<std::mutex> l(m);
      published[last_ns] = ros::WallTime::now();
    }
    events_pub.publish(packet);
    i = j;
  }
  const double publish_s = (ros::WallTime::now() - wall0).toSec();
  // Wait for the last batch and a diagnostics update after it.
  const ros::WallTime done = ros::WallTime::now() + ros::WallDuration(20.0);
  const int64_t last_event = sim.events.back().t_ns;
  size_t diagnostics_at_end = 0;
  for (;;)
  {
    {
      std::lock_guard<std::mutex> l(m);
      if (!lags_s.empty() && diagnostics.size() > diagnostics_at_end + 1 && diagnostics_at_end > 0)
        break;
      if (diagnostics_at_end == 0 && !published.empty() && !lags_s.empty())
        diagnostics_at_end = diagnostics.size();
    }
    if (ros::WallTime::now() > done)
      break;
    ros::WallDuration(0.05).sleep();
  }
  (void)last_event;

  std::lock_guard<std::mutex> l(m);
  const double span_s = (sim.events.back().t_ns - sim.events.front().t_ns) * 1e-9;
  EXPECT_LT(publish_s, span_s / kSpeed * 1.7 + 0.1) << "the publisher itself could not keep 60 % of the intended speed";
  ASSERT_GT(lags_s.size(), 100u);
  std::vector<double> sorted = lags_s;
  std::sort(sorted.begin(), sorted.end());
  const double p50 = sorted[sorted.size() / 2], p99 = sorted[sorted.size() * 99 / 100], max = sorted.back();
  std::printf("overload: %zu events in %.2f s (%.1f M events/s), %zu pose batches, lag publish -> pose: median %.1f ms, "
              "p99 %.1f ms, max %.1f ms\n",
              sim.events.size(), publish_s, sim.events.size() / publish_s * 1e-6, lags_s.size(), 1e3 * p50, 1e3 * p99,
              1e3 * max);
  // The figures in the test report (BENCHMARKS.md).
  ::testing::Test::RecordProperty("events_per_s", std::to_string(sim.events.size() / publish_s));
  ::testing::Test::RecordProperty("lag_median_ms", std::to_string(1e3 * p50));
  ::testing::Test::RecordProperty("lag_p99_ms", std::to_string(1e3 * p99));
  ::testing::Test::RecordProperty("lag_max_ms", std::to_string(1e3 * max));
  // Without the governor the backlog grows with the sequence (seconds). With it: about twice the
  // overload_latency budget (100 ms) plus transport and a slow packet on a loaded machine.
  EXPECT_LT(p99, 0.5);
  EXPECT_LT(max, 1.0);
  ASSERT_FALSE(diagnostics.empty());
  const auto& d = diagnostics.back();
  std::printf("diagnostics: events skipped %s, packets strided %s, stride now %s, packets dropped %s, cost %s us/event\n",
              diagnosticValue(d, "overload: events skipped").c_str(),
              diagnosticValue(d, "overload: packets tracked with a stride").c_str(),
              diagnosticValue(d, "overload: stride now (1: every event tracked)").c_str(),
              diagnosticValue(d, "overload: packets dropped (max_queued_events)").c_str(),
              diagnosticValue(d, "tracking cost [us/event]").c_str());
  ::testing::Test::RecordProperty("events_skipped", diagnosticValue(d, "overload: events skipped"));
  ::testing::Test::RecordProperty("queued_events_at_end", diagnosticValue(d, "queued events"));
  EXPECT_GT(std::stoull(diagnosticValue(d, "overload: events skipped")), 50000u);
  EXPECT_EQ(diagnosticValue(d, "overload: packets dropped (max_queued_events)"), "0");
  // Reported beside the stride (while initialising, whole packets are skipped instead).
  EXPECT_NO_THROW(std::stoull(diagnosticValue(d, "overload: packets skipped whole while initialising")));
  bool warned = false;
  for (const auto& s : diagnostics)
    warned |= s.level == diagnostic_msgs::DiagnosticStatus::WARN && s.message.find("falling behind") != std::string::npos;
  EXPECT_TRUE(warned) << "the overload was not reported at WARN level";
  ASSERT_FALSE(states.empty());
  EXPECT_EQ(states.back(), "TRACKING");
  // Tracking every k-th event still tracks: the batches' last poses against ground truth.
  double sum_sq = 0;
  size_t n = 0;
  for (const auto& p : last_poses)
  {
    const double t = p.header.stamp.toSec();
    const auto it = std::lower_bound(sim.groundtruth.begin(), sim.groundtruth.end(), t,
                                     [](const auto& g, double tt) { return g.t < tt; });
    if (it == sim.groundtruth.end())
      continue;
    const auto& q = p.pose.position;
    sum_sq += (Eigen::Vector3d(q.x, q.y, q.z) - it->T_world_camera.p_world_camera()).squaredNorm();
    ++n;
  }
  ASSERT_GT(n, 100u);
  const double rms = std::sqrt(sum_sq / n);
  ::testing::Test::RecordProperty("rms_position_cm", std::to_string(100 * rms));
  EXPECT_LT(rms, 0.10);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_tracker_overload");
  return RUN_ALL_TESTS();
}
