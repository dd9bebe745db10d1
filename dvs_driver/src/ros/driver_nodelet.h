#pragma once
// dvs_driver/DriverNodelet: a DVS128 (libusb) or a recorded file as dvs_msgs/EventArray packets.
// Thin ROS layer over the core: DeviceInput / FileInput (EventInput), StampMapper, PacketPolicy.
#include <dvs_driver/DvsDriverConfig.h>
#include <dvs_driver/event_input.h>
#include <dvs_driver/packet_builder.h>

#include <camera_info_manager/camera_info_manager.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dvs_msgs/EventArray.h>
#include <dynamic_reconfigure/server.h>
#include <nodelet/nodelet.h>
#include <ros/ros.h>
#include <std_msgs/Time.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>

namespace dvs_driver
{
class DeviceInput;

class DriverNodelet : public nodelet::Nodelet, private EventInputListener
{
public:
  DriverNodelet() = default;
  ~DriverNodelet() override;

private:
  void onInit() override;
  void readParameters(ros::NodeHandle& pnh);

  // EventInputListener (input thread)
  void onEvents(const Event* begin, const Event* end) override;
  void onTimestampReset() override;
  void onTimestampResetRequest() override;
  void onStatus(bool connected, const std::string& message) override;
  void onWarning(const std::string& message) override;
  void onEndOfInput() override;

  void publishPacketLocked();
  void reconfigure(DvsDriverConfig& config, uint32_t level);
  void resetTimestampsReceived(const std_msgs::Time::ConstPtr& msg);
  void publishCameraInfo(const ros::TimerEvent&);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  // Parameters
  std::string file_, serial_, bias_preset_, frame_id_, camera_name_, camera_info_url_, file_time_;
  double replay_speed_ = 1.0, reset_timestamps_delay_ = -1.0, camera_info_rate_ = 30.0, reconnect_interval_ = 0.5;
  bool master_ = true, replay_loop_ = false, wait_for_subscriber_ = false;
  ros::WallTimer start_timer_;
  std::atomic<bool> started_{false};
  int transfers_ = 8, transfer_size_ = 4096;
  int queue_size_param_ = -1;
  size_t queue_size_ = 1000;  // packets per subscriber that ROS holds for a slow subscriber; 0 = unlimited

  ros::Publisher events_pub_, info_pub_, reset_pub_;
  ros::Subscriber reset_sub_;
  ros::Timer info_timer_, diag_timer_, reset_delay_timer_;
  std::mutex cinfo_mutex_;  // cinfo_, camera_name_ after start
  std::unique_ptr<camera_info_manager::CameraInfoManager> cinfo_;
  ros::NodeHandle camera_nh_;
  bool auto_camera_name_ = false;
  std::unique_ptr<diagnostic_updater::Updater> diag_;
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<DvsDriverConfig>> reconfigure_server_;

  std::unique_ptr<EventInput> input_;
  DeviceInput* device_input_ = nullptr;  // input_ when it is the camera

  std::mutex mutex_;  // everything below
  PacketPolicy policy_;
  StampMapper stamps_;
  dvs_msgs::EventArrayPtr packet_;
  int64_t packet_first_ns_ = 0;
  std::chrono::steady_clock::time_point packet_started_;  // wall time the packet got its first event
  ros::WallTimer flush_timer_;
  size_t reserve_ = 1024;
  uint32_t width_ = 128, height_ = 128;
  int64_t replay_first_ns_ = 0;        // time of a recording's first event (file_time replay)
  int64_t pending_reset_ns_ = -1;      // host time of the last reset request not yet seen
  int64_t slave_reset_ns_ = -1;        // the master's reset time a slave adopts
  bool connected_ = false;
  std::string status_message_;
  uint64_t events_published_ = 0, packets_published_ = 0, events_without_subscriber_ = 0, warnings_ = 0;
  uint64_t last_diag_events_ = 0;
  ros::WallTime last_diag_time_;
  bool end_of_input_ = false;
};
}  // namespace dvs_driver
