#pragma once
// ROS wrapper of the line tracker: parameters, subscriptions, publications. The nodelet and
// the node construct this one class; the algorithm lives in LineTracker.
#include <diagnostic_updater/diagnostic_updater.h>
#include <dvs_driver/param_table.h>
#include <dvs_line_tracker/body_odometry.h>
#include <dvs_line_tracker/imu_propagator.h>
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_line_tracker/tracker_params.h>
#include <dvs_msgs/EventArray.h>
#include <image_transport/image_transport.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Imu.h>
#include <tf2_ros/transform_broadcaster.h>

#include <deque>
#include <memory>
#include <mutex>
#include <string>

namespace dvs_line_tracker
{
class TrackerRos
{
public:
  /// Reads and validates the private parameters; throws std::invalid_argument naming a bad one.
  TrackerRos(ros::NodeHandle nh, ros::NodeHandle pnh);
  ~TrackerRos();


private:
  void onCameraInfo(const sensor_msgs::CameraInfoConstPtr& msg);
  void onEvents(const dvs_msgs::EventArrayConstPtr& msg);
  void onImu(const sensor_msgs::ImuConstPtr& msg);
  /// Track the waiting packets whose IMU samples are in (or whose IMU is late). Takes the lock
  /// per packet: call it without holding it.
  void processPending();
  void processPacket(const dvs_msgs::EventArrayConstPtr& msg);
  void onOutputTimer(const ros::TimerEvent& ev);
  /// ~odometry at t_ns (the IMU filter predicted to it, or the vision's pose); nothing before tracking.
  void publishOdometry(int64_t t_ns);
  void startTracker(const dvs_calibration::CameraModel& camera);
  void publishPacket(const dvs_msgs::EventArray& msg, int64_t last_update_ns, bool any_update);
  void publishMarkers(const ros::Time& stamp);
  void publishImage(const dvs_msgs::EventArray& msg);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void reportInputProblems();

  ros::NodeHandle nh_, pnh_;
  LineTrackerParams params_;
  TrackerNodeSettings settings_;
  LineMap map_;
  std::unique_ptr<LineTracker> tracker_;
  std::shared_ptr<ImuPropagator> imu_;
  Pose T_camera_body_;
  std::recursive_mutex mutex_;  ///< the tracker and its IMU (the nodelet's callbacks may run in parallel; diagnostics run inside them)
  int64_t last_event_ns_ = INT64_MIN, last_odometry_ns_ = INT64_MIN;
  struct PendingPacket
  {
    dvs_msgs::EventArrayConstPtr msg;
    ros::WallTime arrival;
  };
  std::deque<PendingPacket> pending_;  ///< event packets waiting for their IMU samples
  uint64_t imu_messages_ = 0, reported_imu_fallbacks_ = 0;
  std::string reported_imu_message_;

  ros::Subscriber events_sub_, camera_info_sub_, imu_sub_;
  ros::Publisher pose_pub_, poses_pub_, markers_pub_, state_pub_, odometry_pub_;
  ros::CallbackQueue output_queue_;  ///< ~output_rate's timer runs in its own thread
  std::unique_ptr<ros::AsyncSpinner> output_spinner_;
  ros::Timer output_timer_;
  ros::WallTimer pending_timer_;
  image_transport::Publisher image_pub_;
  tf2_ros::TransformBroadcaster tf_;
  diagnostic_updater::Updater diagnostics_;
  ros::Timer diagnostics_timer_;
  ros::Time last_image_, last_markers_;

  // Rates for diagnostics.
  uint64_t events_since_diag_ = 0, updates_since_diag_ = 0;
  ros::WallTime last_diag_ = ros::WallTime::now();
  TrackerState last_state_ = TrackerState::kInitializing;
  uint64_t reported_outside_ = 0, reported_time_jumps_ = 0;
};
}  // namespace dvs_line_tracker
