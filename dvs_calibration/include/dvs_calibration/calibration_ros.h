#pragma once
// ROS wrapper of CalibrationSession: events in, preview/pattern/undistorted images and the focus
// score out, services to start, add a view, calibrate, save and reset. Used by the node and the
// nodelet alike. No algorithm here: everything is in the ROS-free core.
#include <dvs_calibration/calibration_session.h>
#include <dvs_calibration/camera_info_conversions.h>
#include <dvs_msgs/EventArray.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <std_srvs/Trigger.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace dvs_calibration
{
class CalibrationRos
{
public:
  /// Reads and validates the private parameters; throws std::invalid_argument naming the
  /// parameter (after logging it with ROS_FATAL).
  CalibrationRos(ros::NodeHandle nh, ros::NodeHandle pnh);

private:
  void readParameters(ros::NodeHandle& pnh);
  void eventsCallback(const dvs_msgs::EventArray::ConstPtr& msg);
  void onWindow(const WindowResult& w);
  bool startService(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool stopService(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool addViewService(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool calibrateService(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool saveService(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool resetService(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);

  ros::NodeHandle nh_, pnh_;
  SessionConfig config_;
  bool start_collecting_ = true;
  bool call_set_camera_info_ = true;
  std::string set_camera_info_service_;
  std::string camera_name_;
  std::string output_file_;
  std::string frame_id_;
  int preview_upscale_ = 4;

  std::mutex mutex_;
  std::unique_ptr<CalibrationSession> session_;  ///< created at the first events (sensor size)
  std::optional<CalibrationResult> result_;
  dvs_driver::EventVector buffer_;
  std::string last_frame_id_ = "dvs";
  ros::Time last_stamp_;

  ros::Subscriber events_sub_;
  ros::Publisher preview_pub_, pattern_pub_, undistorted_pub_, focus_pub_, views_pub_;
  ros::ServiceServer start_srv_, stop_srv_, add_view_srv_, calibrate_srv_, save_srv_, reset_srv_;
  ros::ServiceClient set_camera_info_client_;
};
}  // namespace dvs_calibration
