#pragma once
// ROS wrapper of the line tracker: parameters, subscriptions, publications. The nodelet and
// the node construct this one class; the algorithm lives in LineTracker.
#include <diagnostic_updater/diagnostic_updater.h>
#include <dvs_driver/param_table.h>
#include <dvs_line_tracker/body_odometry.h>
#include <dvs_line_tracker/imu_propagator.h>
#include <dvs_line_tracker/latency_split.h>
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_line_tracker/overload_governor.h>
#include <dvs_line_tracker/tracker_params.h>
#include <dvs_msgs/EventArray.h>
#include <image_transport/image_transport.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Imu.h>
#include <tf2_ros/transform_broadcaster.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

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
  /// The tracking thread: takes the queued packets in order (each when its IMU samples are in)
  /// and tracks them, every event or every k-th when it falls behind (OverloadGovernor). The
  /// callbacks only queue, so the backlog is visible here rather than in ROS's queue.
  void trackingLoop();
  struct PendingPacket
  {
    dvs_msgs::EventArrayConstPtr msg;
    ros::WallTime arrival;
    ros::Time arrival_clock;  ///< the ROS clock at arrival (the events' time base): the latency's transport
  };
  /// Under both locks: the next packet to track (false: none, or it waits for its IMU samples).
  bool nextPacket(PendingPacket& packet);
  /// Track every `stride`-th event of the packet; returns the events given to the tracker.
  /// `start`: when the tracking thread took the packet (the latency's queue and processing).
  /// `event_loop_s` receives the wall time of the loop over the events (what a stride shortens).
  size_t processPacket(const PendingPacket& packet, int stride, ros::WallTime start, double* event_loop_s = nullptr);
  void onOutputTimer(const ros::TimerEvent& ev);
  /// ~odometry at t_ns (the IMU filter predicted to it, or the vision's pose); nothing before tracking.
  void publishOdometry(int64_t t_ns);
  void startTracker(const dvs_calibration::CameraModel& camera);
  void publishPacket(const dvs_msgs::EventArray& msg, int64_t last_update_ns, bool any_update);
  void publishMarkers(const ros::Time& stamp);
  void publishImage(const dvs_msgs::EventArray& msg);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void reportInputProblems();
  /// A warning (at most once per second) when events were skipped or dropped. With queue_mutex_.
  void reportOverload();

  ros::NodeHandle nh_, pnh_;
  LineTrackerParams params_;
  TrackerNodeSettings settings_;
  LineMap map_;
  std::unique_ptr<LineTracker> tracker_;
  std::shared_ptr<ImuPropagator> imu_;
  Pose T_camera_body_;
  std::recursive_mutex mutex_;  ///< the tracker and its IMU (the nodelet's callbacks may run in parallel; diagnostics run inside them)
  int64_t last_event_ns_ = INT64_MIN, last_odometry_ns_ = INT64_MIN;
  LatencySplit latency_;  ///< event -> pose published, in parts (with mutex_; diagnostics)
  // The queue has its own lock, never held for long: the callbacks only queue (they would
  // otherwise wait behind a packet being tracked and the backlog would pile up unseen in ROS's
  // subscriber queue). Lock order: mutex_, then diagnostics_'s own lock (diagnostics are
  // updated only with mutex_ held), then queue_mutex_.
  std::mutex queue_mutex_;
  std::condition_variable wake_;       ///< a packet or an IMU sample came, or stop (with queue_mutex_)
  std::deque<PendingPacket> pending_;  ///< event packets queued for the tracking thread
  size_t pending_events_ = 0;          ///< events in pending_
  bool stopping_ = false;
  std::atomic<bool> tracker_ready_{false};
  OverloadGovernor overload_;          ///< with queue_mutex_
  uint64_t stride_phase_ = 0;          ///< which events a stride keeps, continued across packets
  double queue_wait_max_s_ = 0;        ///< longest wait of a packet in the queue since the last diagnostics
  uint64_t skipped_reported_ = 0, dropped_reported_ = 0, skipped_at_diag_ = 0, dropped_at_diag_ = 0;
  std::thread tracking_thread_;
  uint64_t imu_messages_ = 0, reported_imu_fallbacks_ = 0;
  std::string reported_imu_message_;

  ros::Subscriber events_sub_, camera_info_sub_, imu_sub_;
  ros::Publisher pose_pub_, poses_pub_, markers_pub_, state_pub_, odometry_pub_;
  ros::CallbackQueue output_queue_;  ///< ~output_rate's timer runs in its own thread
  std::unique_ptr<ros::AsyncSpinner> output_spinner_;
  ros::Timer output_timer_;
  image_transport::Publisher image_pub_;
  tf2_ros::TransformBroadcaster tf_;
  diagnostic_updater::Updater diagnostics_;
  ros::Timer diagnostics_timer_;
  ros::Time last_image_, last_markers_;

  // Rates for diagnostics.
  uint64_t events_since_diag_ = 0, updates_since_diag_ = 0;
  ros::WallTime last_diag_ = ros::WallTime::now();
  TrackerState last_state_ = TrackerState::kInitializing;
  bool last_held_ = false;  ///< the ~state last published said "partial view held"
  uint64_t reported_outside_ = 0, reported_time_jumps_ = 0;
};
}  // namespace dvs_line_tracker
