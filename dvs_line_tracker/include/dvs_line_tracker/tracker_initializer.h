#pragma once
// (Re-)initialisation (thesis 4.2.1): the events vote in a Hough accumulator over a sliding
// window; every few hundred voted events the detected segments are filtered (not along the
// image border), assembled into image polygons with the map's side counts, and each polygon's
// corners give a pose (pose_initializer.h), refined on the window's events near the projected
// map (point-to-line), validated (every corner in the image, every side covered by events, a
// quiet inside) and confirmed by an earlier agreeing detection. The confirmed pose is offered
// to the caller, which starts tracking from it or declines (too little of the map in view).
#include <dvs_driver/event.h>
#include <dvs_line_tracker/estimator_state.h>
#include <dvs_line_tracker/hough_line_detector.h>
#include <dvs_line_tracker/polygon_search.h>
#include <dvs_line_tracker/tracker_params.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace dvs_line_tracker
{
class TrackerInitializer
{
public:
  TrackerInitializer(const TrackingGeometry& geometry, const LineTrackerParams& params);

  /// Starts tracking from a confirmed pose; false: declined (the detection window restarts).
  using StartTracking = std::function<bool(const Pose& pose)>;

  /// Feed one event (ideal pixel `p`, the raw event). Returns true when a detection was
  /// confirmed and `start` accepted it.
  bool addEvent(const Eigen::Vector2d& p, const dvs_driver::Event& e, const StartTracking& start);

  /// After a loss or a declined start: empty the window, forget unconfirmed detections.
  void restart();
  /// Everything back to the constructed state.
  void reset();

  /// The image polygon of the last accepted detection (ideal pixels).
  const ImagePolygon& lastPolygon() const { return last_polygon_; }

private:
  bool tryInitialize(const StartTracking& start);
  bool alongBorder(const ImageSegment& segment) const;
  /// A later detection agreeing with `pose` (position / distance and angle bounds) is needed.
  bool confirmed(const Pose& pose);
  Pose refineWithWindowEvents(const Pose& initial) const;
  /// Smallest fraction, over the visible map segments, of 3 px cells along the segment holding
  /// a window event within the attribution distance (0 when a polygon corner is off the image or
  /// the polygon's inside is busy).
  double minSideCoverage(const Pose& pose) const;

  const TrackingGeometry& geometry_;
  const LineTrackerParams& params_;
  HoughLineDetector hough_;
  std::vector<int> side_counts_;   ///< distinct side counts of the map's polygons
  int voted_since_check_ = 0;
  int64_t last_check_ns_ = std::numeric_limits<int64_t>::min() / 2;
  std::vector<Pose> recent_;       ///< the last detections awaiting confirmation
  ImagePolygon last_polygon_;
};
}  // namespace dvs_line_tracker
