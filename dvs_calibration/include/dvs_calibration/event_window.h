#pragma once
// Per-pixel event statistics over one integration window (thesis ch. 2: 75 ms), the input of
// the grid detectors and the focus score. Adding an event allocates nothing.
#include <dvs_driver/event.h>

#include <opencv2/core.hpp>

#include <cstdint>

namespace dvs_calibration
{
/// ON/OFF counts and polarity alternations of every pixel in [t_begin_ns, t_end_ns).
class EventWindow
{
public:
  EventWindow() = default;
  /// Allocates the per-pixel images (all zero). Throws std::invalid_argument for a non-positive size.
  EventWindow(int width, int height);

  /// Clear all counts and start a window at t_begin_ns (no allocation).
  void reset(int64_t t_begin_ns, int64_t t_end_ns);

  /// Count one event. Events outside the sensor are ignored (counted in ignoredEvents()).
  void add(const dvs_driver::Event& e)
  {
    if (e.x >= width_ || e.y >= height_)
    {
      ++ignored_;
      return;
    }
    const int i = e.y * width_ + e.x;
    int8_t& last = last_polarity_.ptr<int8_t>()[i];
    const int8_t p = e.polarity ? 1 : -1;
    if (e.polarity)
      ++on_.ptr<int32_t>()[i];
    else
      ++off_.ptr<int32_t>()[i];
    if (last != 0 && last != p)
      ++transitions_.ptr<int32_t>()[i];
    last = p;
    ++num_events_;
  }

  int width() const { return width_; }
  int height() const { return height_; }
  int64_t beginNs() const { return t_begin_ns_; }
  int64_t endNs() const { return t_end_ns_; }
  size_t numEvents() const { return num_events_; }
  size_t ignoredEvents() const { return ignored_; }

  /// Per-pixel ON + OFF counts (CV_32S). Computed on call.
  cv::Mat counts() const { return on_ + off_; }
  const cv::Mat& onCounts() const { return on_; }           ///< CV_32S
  const cv::Mat& offCounts() const { return off_; }         ///< CV_32S
  const cv::Mat& transitions() const { return transitions_; }  ///< CV_32S, ON<->OFF alternations

private:
  int width_ = 0;
  int height_ = 0;
  int64_t t_begin_ns_ = 0;
  int64_t t_end_ns_ = 0;
  size_t num_events_ = 0;
  size_t ignored_ = 0;
  cv::Mat on_, off_, transitions_, last_polarity_;
};
}  // namespace dvs_calibration
