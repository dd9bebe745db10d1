#include <dvs_calibration/calibration_session.h>
#include <dvs_calibration/camera_model.h>
#include <dvs_calibration/focus_score.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dvs_calibration
{
void validate(const SessionConfig& c)
{
  if (c.width <= 0 || c.height <= 0 || c.width > kMaxSensorSide || c.height > kMaxSensorSide)
    throw std::invalid_argument("width and height must be positive and at most " + std::to_string(kMaxSensorSide) + " (got " + std::to_string(c.width) + "x" +
                                std::to_string(c.height) + ")");
  if (c.window_ns < 1000000 || c.window_ns > 10000000000LL)
    throw std::invalid_argument("window must be between 1 ms and 10 s (got " + std::to_string(c.window_ns * 1e-6) + " ms)");
  if (c.threshold.count_threshold < 0)
    throw std::invalid_argument("count_threshold must be >= 0 (0 = automatic)");
  if (!(c.threshold.auto_threshold_fraction > 0 && c.threshold.auto_threshold_fraction < 1))
    throw std::invalid_argument("auto_threshold_fraction must be in (0, 1)");
  if (c.threshold.min_count_threshold < 1)
    throw std::invalid_argument("min_count_threshold must be >= 1");
  if (c.threshold.closing_size < 0 || c.threshold.closing_size > 15 || c.blink.closing_size < 0 || c.blink.closing_size > 15)
    throw std::invalid_argument("closing_size must be 0..15 pixels");
  if (c.blink.min_transitions < 1)
    throw std::invalid_argument("blink_min_transitions must be >= 1");
  if (!(c.blink.min_polarity_balance >= 0 && c.blink.min_polarity_balance <= 1))
    throw std::invalid_argument("blink_min_polarity_balance must be in [0, 1]");
  if (c.grid.grid.cols < 2 || c.grid.grid.rows < 2)
    throw std::invalid_argument("grid must have at least 2 columns and 2 rows");
  if (c.grid.min_blob_area < 1)
    throw std::invalid_argument("min_blob_area must be >= 1 pixel");
  if (!(c.grid.max_homography_rms_px > 0))
    throw std::invalid_argument("max_homography_rms must be > 0 pixels");
  if (!(c.views.min_view_difference_px >= 0))
    throw std::invalid_argument("min_view_difference must be >= 0 pixels");
  if (c.views.max_views < 1)
    throw std::invalid_argument("max_views must be >= 1");
  if (!(c.max_motion_px > 0))
    throw std::invalid_argument("max_motion must be > 0 pixels");
  CalibratorConfig cal = c.calibrator;
  cal.grid = c.grid.grid;
  validate(cal);
}

CalibrationSession::CalibrationSession(const SessionConfig& config)
  : config_(config), views_(config.grid.grid, config.views)
{
  validate(config_);
  config_.calibrator.grid = config_.grid.grid;
  const size_t phases = config_.overlap_windows ? 2 : 1;
  for (size_t p = 0; p < phases; ++p)
  {
    windows_.emplace_back(config_.width, config_.height);
    phase_offset_ns_.push_back(static_cast<int64_t>(p) * config_.window_ns / 2);
  }
}

void CalibrationSession::startWindow(size_t phase, int64_t t_ns)
{
  // Windows aligned to multiples of the window length plus the phase offset (floor division,
  // negative times too).
  const int64_t t = t_ns - phase_offset_ns_[phase];
  int64_t k = t / config_.window_ns;
  if (t < 0 && k * config_.window_ns != t)
    --k;
  const int64_t begin = k * config_.window_ns + phase_offset_ns_[phase];
  windows_[phase].reset(begin, begin + config_.window_ns);
}

void CalibrationSession::addEvents(const dvs_driver::Event* begin, const dvs_driver::Event* end)
{
  for (const dvs_driver::Event* e = begin; e != end; ++e)
  {
    if (!window_open_)
    {
      for (size_t p = 0; p < windows_.size(); ++p)
        startWindow(p, e->t_ns);
      window_open_ = true;
    }
    else if (e->t_ns < windows_[0].beginNs() && e->t_ns < windows_.back().beginNs())
    {
      // Time went backwards (a replayed recording): close what we have, start over.
      flush();
      previous_detection_ = GridDetection();
      for (size_t p = 0; p < windows_.size(); ++p)
        startWindow(p, e->t_ns);
      window_open_ = true;
    }
    else
    {
      // Close the windows this event is past, earliest end first (results in time order).
      for (;;)
      {
        size_t first = windows_.size();
        for (size_t p = 0; p < windows_.size(); ++p)
          if (e->t_ns >= windows_[p].endNs() && (first == windows_.size() || windows_[p].endNs() < windows_[first].endNs()))
            first = p;
        if (first == windows_.size())
          break;
        processWindow(windows_[first]);
        startWindow(first, e->t_ns);
      }
    }
    for (EventWindow& w : windows_)
      w.add(*e);
  }
}

void CalibrationSession::flush()
{
  if (!window_open_)
    return;
  std::vector<size_t> order(windows_.size());
  for (size_t p = 0; p < order.size(); ++p)
    order[p] = p;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return windows_[a].endNs() < windows_[b].endNs(); });
  for (size_t p : order)
    if (windows_[p].numEvents() > 0)
      processWindow(windows_[p]);
  window_open_ = false;
}

void CalibrationSession::processWindow(const EventWindow& window)
{
  ++windows_processed_;
  WindowResult r;
  r.t_begin_ns = window.beginNs();
  r.t_end_ns = window.endNs();
  r.num_events = window.numEvents();
  r.counts = window.counts();
  r.focus_score = focusScore(r.counts);
  WindowDetection wd = detectGridInWindow(window, config_.detector, config_.threshold, config_.blink, config_.grid);
  r.binary = wd.binary;
  r.threshold = wd.threshold;
  r.detection = std::move(wd.detection);
  if (r.detection.found)
  {
    ++detections_;
    r.stable = previous_detection_.found &&
               meanNearestDistance(r.detection.centers, previous_detection_.centers) <= config_.max_motion_px;
    if (r.stable)
    {
      ++stable_detections_;
      const bool wanted = view_requested_ || (config_.auto_collect && views_.isNovel(r.detection.centers));
      if (collecting_ && wanted)
      {
        View v;
        v.centers = r.detection.centers;
        v.t_ns = r.t_end_ns;
        r.view_added = views_.add(v);
        if (r.view_added)
          view_requested_ = false;
      }
    }
  }
  previous_detection_ = r.detection;
  last_ = r;
  if (callback_)
    callback_(last_);
}

void CalibrationSession::reset()
{
  views_.clear();
  previous_detection_ = GridDetection();
  last_ = WindowResult();
  window_open_ = false;
  view_requested_ = false;
  windows_processed_ = detections_ = stable_detections_ = 0;
}

CalibrationResult CalibrationSession::calibrate() const
{
  std::vector<std::vector<cv::Point2f>> pts;
  for (const View& v : views_.views())
    pts.push_back(v.centers);
  return calibrateIntrinsics(pts, config_.width, config_.height, config_.calibrator);
}
}  // namespace dvs_calibration
