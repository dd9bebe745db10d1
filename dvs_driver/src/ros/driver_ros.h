#pragma once
// DriverRos: the ROS side of the driver, constructed by the nodelet dvs_driver/DriverNodelet and
// by the node dvs_driver_node alike. It reads and validates the parameters (driver_params.h),
// opens the event input (the camera: DeviceInput; a recording: FileReplay streaming an
// EventSource), owns the publishers, services, timers, diagnostics and dynamic_reconfigure, and
// turns the input's events into dvs_msgs/EventArray packets (PacketBuilder decides when).
#include <dvs_driver/DvsDriverConfig.h>
#include <dvs_driver/driver_params.h>
#include <dvs_driver/dvs128_biases.h>
#include <dvs_driver/event_input.h>
#include <dvs_driver/packet_builder.h>

#include <camera_info_manager/camera_info_manager.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dvs_msgs/EventArray.h>
#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>
#include <std_msgs/Time.h>

#include <atomic>
#include <memory>
#include <mutex>

namespace dvs_driver
{
class DeviceInput;
class FileReplay;

class DriverRos : private EventInputListener
{
public:
  /// Topics go under `nh`/dvs, parameters come from `pnh`. Starts streaming (or waits for a
  /// subscriber, ~wait_for_subscriber) and returns at once. Throws std::invalid_argument with a
  /// message naming the parameter when one is invalid (the file included).
  DriverRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
  ~DriverRos() override;

private:
  struct MessageSink;
  void readParameters();
  void openFile();
  void openCamera();
  void advertise();
  void start();

  // EventInputListener (input thread)
  void onEvents(const Event* begin, const Event* end) override;
  void onTimestampReset() override;
  void onTimestampResetRequest() override;
  void onStatus(bool connected, const std::string& message) override;
  void onWarning(const std::string& message) override;
  void onEndOfInput() override;
  void onInputError(const std::string& message) override;

  void publishPacketLocked();
  void reconfigure(DvsDriverConfig& config, uint32_t level);
  void resetTimestampsReceived(const std_msgs::Time::ConstPtr& msg);
  void publishCameraInfo(const ros::TimerEvent&);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  ros::NodeHandle nh_, pnh_;
  DriverParams params_;
  Dvs128Biases biases_;
  size_t queue_size_ = 1000;  // packets per subscriber that ROS holds for a slow subscriber; 0 = unlimited
  std::string camera_name_;
  ros::WallTimer start_timer_;
  std::atomic<bool> started_{false};

  ros::Publisher events_pub_, info_pub_, reset_pub_;
  ros::Subscriber reset_sub_;
  ros::Timer info_timer_, diag_timer_, reset_delay_timer_;
  std::mutex cinfo_mutex_;  // cinfo_, camera_name_ after start
  std::unique_ptr<camera_info_manager::CameraInfoManager> cinfo_;
  bool auto_camera_name_ = false;
  std::unique_ptr<diagnostic_updater::Updater> diag_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<DvsDriverConfig>> reconfigure_server_;

  std::unique_ptr<EventInput> input_;
  DeviceInput* device_input_ = nullptr;  // input_ when it is the camera
  FileReplay* replay_ = nullptr;         // input_ when it is a recording

  std::mutex mutex_;  // everything below
  PacketBuilder builder_;
  dvs_msgs::EventArrayPtr packet_;
  ros::WallTimer flush_timer_;
  size_t reserve_ = 1024;
  uint32_t width_ = 128, height_ = 128;
  std::string file_format_;            // a recording's detected format (for the log)
  int64_t replay_first_ns_ = 0;        // time of a recording's first event (file_time replay)
  int64_t pending_reset_ns_ = -1;      // host time of the last reset request not yet seen
  int64_t slave_reset_ns_ = -1;        // the master's reset time a slave adopts
  bool connected_ = false;
  std::string status_message_;
  std::string input_error_;
  uint64_t events_published_ = 0, packets_published_ = 0, events_without_subscriber_ = 0, warnings_ = 0;
  uint64_t last_diag_events_ = 0;
  ros::WallTime last_diag_time_;
  bool end_of_input_ = false;
};
}  // namespace dvs_driver
