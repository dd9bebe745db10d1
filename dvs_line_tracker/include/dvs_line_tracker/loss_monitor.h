#pragma once
// Tracking-quality monitoring: every `quality_check_interval` events while tracking, the
// estimate is checked (finite, the map in front of the camera, enough visible segments, small
// residuals, attribution not collapsed); the first failed check is the reason the track is lost.
// Attribution has collapsed when fewer than `min_attributed_ratio` of the events were attributed
// and no more than 1.5x what chance gives: background events land in the attribution bands of the
// visible segments in proportion to the bands' share of the image, so on a large, noisy sensor
// in slow motion a good track attributes few events, yet more than chance.
#include <dvs_line_tracker/estimator_state.h>
#include <dvs_line_tracker/tracker_params.h>

#include <cstdint>
#include <string>

namespace dvs_line_tracker
{
/// Mean |point-to-line| distance (px) over all buffered points of visible segments.
double meanResidualPx(const EstimatorState& state);

class LossMonitor
{
public:
  /// `image_area_px`: width x height (0: unknown, the attribution check is the fixed ratio only).
  explicit LossMonitor(const LineTrackerParams& params, double image_area_px = 0)
    : params_(params), image_area_px_(image_area_px)
  {
  }

  /// Count one event processed while tracking.
  void countEvent(bool attributed)
  {
    ++events_;
    attributed_ += attributed ? 1 : 0;
  }
  /// A check is due (every quality_check_interval events).
  bool due() const { return events_ >= static_cast<uint64_t>(params_.quality_check_interval); }
  /// "" while the track is good, else why it is lost. Starts the next interval. Expects the
  /// state's visibility refreshed (EventUpdater::refresh).
  std::string check(const EstimatorState& state);
  /// A new interval (tracking starts).
  void reset() { events_ = attributed_ = 0; }

private:
  const LineTrackerParams& params_;
  double image_area_px_;
  uint64_t events_ = 0, attributed_ = 0;
};
}  // namespace dvs_line_tracker
