#pragma once
// Tracking-quality monitoring: every `quality_check_interval` events while tracking, the
// estimate is checked (finite, the map in front of the camera, enough visible segments, small
// residuals, attribution not collapsed); the first failed check is the reason the track is lost.
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
  explicit LossMonitor(const LineTrackerParams& params) : params_(params) {}

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
  uint64_t events_ = 0, attributed_ = 0;
};
}  // namespace dvs_line_tracker
