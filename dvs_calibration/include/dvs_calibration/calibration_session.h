#pragma once
// One calibration session, ROS-free: events in, windows integrated, the grid detected, views
// collected, the camera calibrated. The node and the offline tool both drive this class.
#include <dvs_calibration/event_window.h>
#include <dvs_calibration/grid_detector.h>
#include <dvs_calibration/intrinsic_calibrator.h>
#include <dvs_calibration/view_collector.h>
#include <dvs_driver/event.h>

#include <functional>
#include <string>
#include <vector>

namespace dvs_calibration
{
struct SessionConfig
{
  int width = 128;
  int height = 128;
  /// Integration window, nanoseconds (thesis: 75 ms).
  int64_t window_ns = 75000000;
  /// Also integrate windows shifted by half a window (a result every window_ns / 2): twice the
  /// chances to catch the grid while the camera is held still.
  bool overlap_windows = true;
  DetectorKind detector = DetectorKind::Counts;
  CountThresholdConfig threshold;
  BlinkDetectorConfig blink;
  GridDetectorConfig grid;  ///< grid.grid is the grid size
  ViewCollectorConfig views;
  CalibratorConfig calibrator;  ///< its grid is overwritten with grid.grid
  /// Keep views automatically (when novel); otherwise only on requestView().
  bool auto_collect = true;
  /// A detection is kept only when the previous window found the grid at nearly the same place
  /// (mean centre motion below this, pixels): rejects views smeared by camera motion.
  double max_motion_px = 0.5;
};

/// Throws std::invalid_argument naming the bad parameter.
void validate(const SessionConfig& config);

/// What one window gave.
struct WindowResult
{
  int64_t t_begin_ns = 0;
  int64_t t_end_ns = 0;
  size_t num_events = 0;
  cv::Mat counts;  ///< CV_32S ON + OFF counts
  cv::Mat binary;  ///< CV_8U pattern image the detector used
  int threshold = 0;
  GridDetection detection;
  bool stable = false;      ///< found, and the previous window found it at the same place
  bool view_added = false;  ///< kept as a calibration view
  double focus_score = 0;
};

class CalibrationSession
{
public:
  using WindowCallback = std::function<void(const WindowResult&)>;

  /// Validates the configuration (std::invalid_argument).
  explicit CalibrationSession(const SessionConfig& config);

  /// Feed events (sorted by time). Each completed window is processed and reported to the
  /// callback. A time step backwards (e.g. a replayed bag) starts a new window.
  void addEvents(const dvs_driver::Event* begin, const dvs_driver::Event* end);
  void addEvents(const dvs_driver::EventVector& events) { addEvents(events.data(), events.data() + events.size()); }
  /// Process the current, incomplete window now (end of a file).
  void flush();

  void setWindowCallback(WindowCallback cb) { callback_ = std::move(cb); }
  /// Collecting views on/off (the "start" service turns it on; on by default).
  void setCollecting(bool on) { collecting_ = on; }
  bool collecting() const { return collecting_; }
  /// Keep the next stable detection even when it is not novel.
  void requestView() { view_requested_ = true; }
  /// Forget views and windows.
  void reset();

  /// Calibrate from the views kept (CalibrationError when too few).
  CalibrationResult calibrate() const;

  const SessionConfig& config() const { return config_; }
  const ViewCollector& views() const { return views_; }
  const WindowResult& lastWindow() const { return last_; }
  size_t windowsProcessed() const { return windows_processed_; }
  size_t detections() const { return detections_; }
  size_t stableDetections() const { return stable_detections_; }

private:
  void startWindow(size_t phase, int64_t t_ns);
  void processWindow(const EventWindow& window);

  SessionConfig config_;
  std::vector<EventWindow> windows_;  ///< one per phase (2 with overlap_windows)
  std::vector<int64_t> phase_offset_ns_;
  bool window_open_ = false;
  ViewCollector views_;
  WindowResult last_;
  GridDetection previous_detection_;
  WindowCallback callback_;
  bool collecting_ = true;
  bool view_requested_ = false;
  size_t windows_processed_ = 0, detections_ = 0, stable_detections_ = 0;
};
}  // namespace dvs_calibration
