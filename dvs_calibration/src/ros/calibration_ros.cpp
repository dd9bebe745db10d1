#include <dvs_calibration/calibration_node_params.h>
#include <dvs_calibration/calibration_report.h>
#include <dvs_calibration/calibration_ros.h>
#include <dvs_calibration/event_image.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/param_table_ros.h>

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/SetCameraInfo.h>
#include <sensor_msgs/image_encodings.h>
#include <std_msgs/Float64.h>
#include <std_msgs/UInt32.h>

#include <cstdlib>
#include <sys/stat.h>

namespace dvs_calibration
{
namespace
{
std::string defaultOutputFile(const std::string& camera_name)
{
  std::string home;
  if (const char* rh = std::getenv("ROS_HOME"))
    home = rh;
  else if (const char* h = std::getenv("HOME"))
    home = std::string(h) + "/.ros";
  else
    home = ".";
  return home + "/camera_info/" + camera_name + ".yaml";
}

void makeParentDirs(const std::string& path)
{
  for (size_t i = 1; i < path.size(); ++i)
    if (path[i] == '/')
      ::mkdir(path.substr(0, i).c_str(), 0755);
}
}  // namespace

CalibrationRos::CalibrationRos(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh)
{
  readParameters(pnh_);
  preview_pub_ = pnh_.advertise<sensor_msgs::Image>("preview", 1);
  pattern_pub_ = pnh_.advertise<sensor_msgs::Image>("pattern", 1);
  undistorted_pub_ = pnh_.advertise<sensor_msgs::Image>("undistorted", 1);
  focus_pub_ = pnh_.advertise<std_msgs::Float64>("focus_score", 10);
  views_pub_ = pnh_.advertise<std_msgs::UInt32>("views", 1, true);
  start_srv_ = pnh_.advertiseService("start", &CalibrationRos::startService, this);
  stop_srv_ = pnh_.advertiseService("stop", &CalibrationRos::stopService, this);
  add_view_srv_ = pnh_.advertiseService("add_view", &CalibrationRos::addViewService, this);
  calibrate_srv_ = pnh_.advertiseService("calibrate", &CalibrationRos::calibrateService, this);
  save_srv_ = pnh_.advertiseService("save", &CalibrationRos::saveService, this);
  reset_srv_ = pnh_.advertiseService("reset", &CalibrationRos::resetService, this);
  set_camera_info_client_ = nh_.serviceClient<sensor_msgs::SetCameraInfo>(set_camera_info_service_);
  events_sub_ = nh_.subscribe("dvs/events", 1000, &CalibrationRos::eventsCallback, this);
  std_msgs::UInt32 zero;
  views_pub_.publish(zero);
  ROS_INFO_STREAM("dvs_calibration: " << config_.grid.grid.cols << "x" << config_.grid.grid.rows << " grid, spacing "
                                      << config_.calibrator.spacing_m << " m, " << toString(config_.detector)
                                      << " detector, window " << config_.window_ns * 1e-6 << " ms; listening on "
                                      << events_sub_.getTopic());
}

void CalibrationRos::readParameters(ros::NodeHandle& pnh)
{
  // Every parameter from one table (calibration_node_params.h): ROS overrides the defaults,
  // unknown names are warned about, ranges validated (throws naming the parameter).
  CalibrationNodeParams p;
  dvs_driver::ParamTable table = calibrationParamTable(p);
  double window_ms = 0;
  if (pnh.getParam("window_ms", window_ms))
  {
    ROS_WARN("dvs_calibration: ~window_ms is deprecated: use ~window in seconds (%g ms read as %g s)", window_ms,
             window_ms * 1e-3);
    p.window_s = window_ms * 1e-3;
  }
  try
  {
    dvs_driver::loadRosParams(pnh, table, {"window_ms"});
    config_ = toSessionConfig(p);
    // Validate the whole session configuration now (the sensor size is checked when known).
    SessionConfig check = config_;
    check.width = check.width > 0 ? check.width : 128;
    check.height = check.height > 0 ? check.height : 128;
    validate(check);
  }
  catch (const std::exception& e)
  {
    ROS_FATAL_STREAM("dvs_calibration: " << e.what());
    throw std::invalid_argument(std::string("dvs_calibration: ") + e.what());
  }
  start_collecting_ = p.start_collecting;
  call_set_camera_info_ = p.call_set_camera_info;
  set_camera_info_service_ = p.set_camera_info_service;
  camera_name_ = p.camera_name;
  frame_id_ = p.frame_id;
  preview_upscale_ = p.preview_upscale;
  output_file_ = p.output_file.empty() ? defaultOutputFile(camera_name_) : p.output_file;
}

void CalibrationRos::eventsCallback(const dvs_msgs::EventArray::ConstPtr& msg)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!session_)
  {
    SessionConfig c = config_;
    if (c.width == 0)
    {
      c.width = msg->width > 0 ? static_cast<int>(msg->width) : 128;
      c.height = msg->height > 0 ? static_cast<int>(msg->height) : 128;
    }
    session_ = std::make_unique<CalibrationSession>(c);
    session_->setCollecting(start_collecting_);
    session_->setWindowCallback([this](const WindowResult& w) { onWindow(w); });
    ROS_INFO_STREAM("dvs_calibration: sensor " << c.width << "x" << c.height
                                               << (start_collecting_ ? ", collecting views" : ", call ~start to collect views"));
  }
  last_frame_id_ = msg->header.frame_id.empty() ? frame_id_ : msg->header.frame_id;
  last_stamp_ = msg->header.stamp;
  buffer_.clear();
  dvs_driver::appendFromMessage(*msg, buffer_);
  session_->addEvents(buffer_);
}

void CalibrationRos::onWindow(const WindowResult& w)
{
  std_msgs::Header header;
  header.stamp = last_stamp_;
  header.frame_id = last_frame_id_;
  std_msgs::Float64 score;
  score.data = w.focus_score;
  focus_pub_.publish(score);
  if (w.view_added)
  {
    std_msgs::UInt32 n;
    n.data = static_cast<uint32_t>(session_->views().size());
    views_pub_.publish(n);
    ROS_INFO_STREAM("dvs_calibration: view " << n.data << " kept");
  }
  if (preview_pub_.getNumSubscribers() > 0)
  {
    const cv::Mat img = renderPreview(w.counts, w.detection.centers, config_.grid.grid.cols, w.focus_score,
                                      preview_upscale_);
    preview_pub_.publish(cv_bridge::CvImage(header, sensor_msgs::image_encodings::BGR8, img).toImageMsg());
  }
  if (pattern_pub_.getNumSubscribers() > 0)
    pattern_pub_.publish(cv_bridge::CvImage(header, sensor_msgs::image_encodings::MONO8, w.binary).toImageMsg());
  if (result_ && undistorted_pub_.getNumSubscribers() > 0 && result_->camera.width() == w.counts.cols &&
      result_->camera.height() == w.counts.rows)
  {
    const cv::Mat und = countsToImage(undistortCounts(w.counts, result_->camera));
    undistorted_pub_.publish(cv_bridge::CvImage(header, sensor_msgs::image_encodings::MONO8, und).toImageMsg());
  }
}

bool CalibrationRos::startService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
{
  std::lock_guard<std::mutex> lock(mutex_);
  start_collecting_ = true;
  if (session_)
    session_->setCollecting(true);
  res.success = true;
  res.message = "collecting views";
  return true;
}

bool CalibrationRos::stopService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
{
  std::lock_guard<std::mutex> lock(mutex_);
  start_collecting_ = false;
  if (session_)
    session_->setCollecting(false);
  res.success = true;
  res.message = "not collecting views";
  return true;
}

bool CalibrationRos::addViewService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!session_)
  {
    res.success = false;
    res.message = "no events received yet";
    return true;
  }
  session_->setCollecting(true);
  session_->requestView();
  res.success = true;
  res.message = "the next still detection of the grid will be kept";
  return true;
}

bool CalibrationRos::calibrateService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
{
  std::lock_guard<std::mutex> lock(mutex_);
  CalibrationSummary summary;
  if (!session_)
  {
    res.success = false;
    res.message = "no events received yet";
    return true;
  }
  summary.windows = session_->windowsProcessed();
  summary.detections = session_->detections();
  summary.views_collected = session_->views().size();
  try
  {
    result_ = session_->calibrate();
  }
  catch (const std::exception& e)
  {
    summary.error = e.what();
    res.success = false;
    res.message = toJson(summary);
    ROS_WARN_STREAM("dvs_calibration: calibration failed: " << e.what());
    return true;
  }
  summary.result = &*result_;
  res.success = true;
  res.message = toJson(summary);
  ROS_INFO_STREAM("dvs_calibration: " << res.message);
  if (call_set_camera_info_)
  {
    sensor_msgs::SetCameraInfo srv;
    srv.request.camera_info = toCameraInfoMsg(result_->camera, last_frame_id_);
    if (!set_camera_info_client_.exists())
      ROS_WARN_STREAM("dvs_calibration: " << set_camera_info_client_.getService()
                                          << " is not available: the driver was not updated (use ~save)");
    else if (!set_camera_info_client_.call(srv) || !srv.response.success)
      ROS_WARN_STREAM("dvs_calibration: " << set_camera_info_client_.getService()
                                          << " failed: " << srv.response.status_message);
    else
      ROS_INFO_STREAM("dvs_calibration: sent the calibration to " << set_camera_info_client_.getService());
  }
  return true;
}

bool CalibrationRos::saveService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!result_)
  {
    res.success = false;
    res.message = "not calibrated yet: call ~calibrate first";
    return true;
  }
  try
  {
    makeParentDirs(output_file_);
    saveCameraInfoYaml(output_file_, result_->camera, camera_name_);
  }
  catch (const std::exception& e)
  {
    res.success = false;
    res.message = e.what();
    return true;
  }
  res.success = true;
  res.message = output_file_;
  ROS_INFO_STREAM("dvs_calibration: saved " << output_file_);
  return true;
}

bool CalibrationRos::resetService(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (session_)
    session_->reset();
  result_.reset();
  std_msgs::UInt32 zero;
  views_pub_.publish(zero);
  res.success = true;
  res.message = "views and calibration cleared";
  return true;
}
}  // namespace dvs_calibration
