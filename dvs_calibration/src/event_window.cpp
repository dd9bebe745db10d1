#include <dvs_calibration/camera_model.h>
#include <dvs_calibration/event_window.h>

#include <stdexcept>
#include <string>

namespace dvs_calibration
{
EventWindow::EventWindow(int width, int height) : width_(width), height_(height)
{
  if (width <= 0 || height <= 0 || width > kMaxSensorSide || height > kMaxSensorSide)
    throw std::invalid_argument("event window size must be positive and at most " + std::to_string(kMaxSensorSide) + " (got " + std::to_string(width) +
                                "x" + std::to_string(height) + ")");
  on_ = cv::Mat::zeros(height, width, CV_32S);
  off_ = cv::Mat::zeros(height, width, CV_32S);
  transitions_ = cv::Mat::zeros(height, width, CV_32S);
  last_polarity_ = cv::Mat::zeros(height, width, CV_8S);
}

void EventWindow::reset(int64_t t_begin_ns, int64_t t_end_ns)
{
  t_begin_ns_ = t_begin_ns;
  t_end_ns_ = t_end_ns;
  num_events_ = 0;
  ignored_ = 0;
  on_.setTo(0);
  off_.setTo(0);
  transitions_.setTo(0);
  last_polarity_.setTo(0);
}
}  // namespace dvs_calibration
