#include <dvs_calibration/calibration_report.h>
#include <dvs_calibration/calibration_ros.h>
#include <dvs_calibration/event_image.h>
#include <dvs_driver/event_bag_io.h>

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
[[noreturn]] void badParameter(const std::string& name, const std::string& why)
{
  ROS_FATAL_STREAM("dvs_calibration: parameter ~" << name << ": " << why);
  throw std::invalid_argument("dvs_calibration: parameter ~" + name + ": " + why);
}

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
  std::string grid, detector;
  double window_ms, spacing, min_view_difference, max_motion, max_homography_rms, outlier_factor;
  int width, height, count_threshold, closing_size, blink_min_transitions, max_views, min_views;
  bool estimate_k3, auto_collect;
  pnh.param<std::string>("grid", grid, "7x7");
  pnh.param("spacing", spacing, 0.03);
  pnh.param("width", width, 0);
  pnh.param("height", height, 0);
  pnh.param("window_ms", window_ms, 75.0);
  pnh.param<std::string>("detector", detector, "counts");
  pnh.param("count_threshold", count_threshold, 0);
  pnh.param("closing_size", closing_size, 3);
  pnh.param("blink_min_transitions", blink_min_transitions, 2);
  pnh.param("auto_collect", auto_collect, true);
  pnh.param("start_collecting", start_collecting_, true);
  pnh.param("min_view_difference", min_view_difference, 8.0);
  pnh.param("max_motion", max_motion, 0.5);
  pnh.param("max_views", max_views, 200);
  pnh.param("max_homography_rms", max_homography_rms, 1.5);
  pnh.param("min_views", min_views, 8);
  pnh.param("outlier_factor", outlier_factor, 3.0);
  pnh.param("estimate_k3", estimate_k3, false);
  pnh.param<std::string>("camera_name", camera_name_, "dvs");
  pnh.param<std::string>("output_file", output_file_, "");
  pnh.param<std::string>("set_camera_info_service", set_camera_info_service_, "dvs/set_camera_info");
  pnh.param("call_set_camera_info", call_set_camera_info_, true);
  pnh.param<std::string>("frame_id", frame_id_, "dvs");
  pnh.param("preview_upscale", preview_upscale_, 4);

  try
  {
    config_.grid.grid = parseGridSize(grid);
  }
  catch (const std::exception& e)
  {
    badParameter("grid", e.what());
  }
  try
  {
    config_.detector = parseDetectorKind(detector);
  }
  catch (const std::exception& e)
  {
    badParameter("detector", e.what());
  }
  if (!(spacing > 0) || spacing > 10)
    badParameter("spacing", "must be the centre-to-centre circle distance in metres, in (0, 10], got " +
                                std::to_string(spacing));
  if (width < 0 || height < 0 || width > 65535 || height > 65535 || ((width == 0) != (height == 0)))
    badParameter("width", "width and height must both be 0 (take the size from the events) or both positive");
  if (!(window_ms >= 1 && window_ms <= 10000))
    badParameter("window_ms", "must be in [1, 10000] ms, got " + std::to_string(window_ms));
  if (count_threshold < 0)
    badParameter("count_threshold", "must be >= 0 (0 = automatic), got " + std::to_string(count_threshold));
  if (closing_size < 0 || closing_size > 15)
    badParameter("closing_size", "must be 0..15 pixels, got " + std::to_string(closing_size));
  if (blink_min_transitions < 1)
    badParameter("blink_min_transitions", "must be >= 1, got " + std::to_string(blink_min_transitions));
  if (!(min_view_difference >= 0))
    badParameter("min_view_difference", "must be >= 0 pixels");
  if (!(max_motion > 0))
    badParameter("max_motion", "must be > 0 pixels");
  if (max_views < 1)
    badParameter("max_views", "must be >= 1");
  if (!(max_homography_rms > 0))
    badParameter("max_homography_rms", "must be > 0 pixels");
  if (min_views < 3)
    badParameter("min_views", "must be >= 3, got " + std::to_string(min_views));
  if (!(outlier_factor > 1))
    badParameter("outlier_factor", "must be > 1");
  if (camera_name_.empty())
    badParameter("camera_name", "must not be empty");
  if (set_camera_info_service_.empty())
    badParameter("set_camera_info_service", "must not be empty");
  if (preview_upscale_ < 1 || preview_upscale_ > 16)
    badParameter("preview_upscale", "must be 1..16");
  if (output_file_.empty())
    output_file_ = defaultOutputFile(camera_name_);

  config_.width = width;
  config_.height = height;
  config_.window_ns = static_cast<int64_t>(window_ms * 1e6 + 0.5);
  config_.threshold.count_threshold = count_threshold;
  config_.threshold.closing_size = closing_size;
  config_.blink.closing_size = closing_size;
  config_.blink.min_transitions = blink_min_transitions;
  config_.auto_collect = auto_collect;
  config_.views.min_view_difference_px = min_view_difference;
  config_.views.max_views = static_cast<size_t>(max_views);
  config_.max_motion_px = max_motion;
  config_.grid.max_homography_rms_px = max_homography_rms;
  config_.calibrator.spacing_m = spacing;
  config_.calibrator.min_views = static_cast<size_t>(min_views);
  config_.calibrator.outlier_factor = outlier_factor;
  config_.calibrator.estimate_k3 = estimate_k3;
  // Validate the whole session configuration now (sensor size is checked when known).
  SessionConfig check = config_;
  check.width = check.width > 0 ? check.width : 128;
  check.height = check.height > 0 ? check.height : 128;
  try
  {
    validate(check);
  }
  catch (const std::exception& e)
  {
    badParameter("(session)", e.what());
  }
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
