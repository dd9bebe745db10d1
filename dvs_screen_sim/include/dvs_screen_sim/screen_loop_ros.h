#pragma once
// The screen_loop node's ROS class: a real DVS filming the screen (thesis ch. 3). It reads the
// parameters (one table, screen_loop/screen_loop_params.h), feeds dvs/events into a
// LiveEventCollector, opens the window (WindowScreen) and runs the ROS-free
// ScreenLoopProcedure on them: refresh period, alignment, apparent-motion check, playback with
// the ground truth published live (dvs/ground_truth/pose, /tf) and optionally recorded with the
// events to a bag (time stamps rescaled to trajectory time). A node, not a nodelet: it owns the
// OpenGL window and its render loop on the main thread.
#include <dvs_msgs/EventArray.h>
#include <dvs_screen_sim/screen_loop/live_event_collector.h>
#include <dvs_screen_sim/screen_loop/screen_loop_params.h>
#include <dvs_screen_sim/sim_config.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <memory>

namespace dvs_screen_sim
{
class ScreenLoopRos
{
public:
  /// Reads and validates the parameters (throws std::invalid_argument naming the bad one), loads
  /// the scenario and the camera, subscribes and advertises.
  ScreenLoopRos(ros::NodeHandle nh, ros::NodeHandle pnh);
  /// Runs the procedure; returns the process exit code (0: played, 1: alignment failed).
  int run();

private:
  void onEvents(const dvs_msgs::EventArray::ConstPtr& msg);
  void writeBag(const screen_loop::Playback& playback) const;

  ros::NodeHandle nh_, pnh_;
  screen_loop::ScreenLoopParams params_;
  SimConfig config_;
  std::unique_ptr<Trajectory> trajectory_;
  dvs_calibration::CameraModel camera_;
  screen_loop::LiveEventCollector events_;
  dvs_driver::EventVector packet_;  ///< conversion buffer of the callback (reused)
  ros::Subscriber sub_;
  ros::Publisher pose_pub_;
  tf2_ros::TransformBroadcaster tf_;
};
}  // namespace dvs_screen_sim
