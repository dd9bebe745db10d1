#pragma once
// The event-based 6-DoF line tracker (thesis ch. 4): initialises from a Hough / polygon search
// over the recent events, then attributes every event to the projected map segments and
// updates the pose after each attributed event. Monitors the tracking quality and
// re-initialises by itself when the track is lost.
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/event.h>
#include <dvs_line_tracker/camera_pose.h>
#include <dvs_line_tracker/edge_run_model.h>
#include <dvs_line_tracker/hough_line_detector.h>
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/polygon_search.h>
#include <dvs_line_tracker/pose_estimator.h>
#include <dvs_line_tracker/pose_initializer.h>
#include <dvs_line_tracker/segment_attribution.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace dvs_line_tracker
{
enum class TrackerState
{
  kInitializing,  ///< looking for the map's polygon (never tracked yet)
  kTracking,      ///< pose updated per event
  kLost,          ///< track lost; looking for the polygon again (re-initialisation)
};
const char* toString(TrackerState state);

struct LineTrackerParams
{
  HoughParams hough;
  PolygonSearchParams polygon;
  PoseInitParams init;
  AttributionParams attribution;
  PoseEstimatorParams estimator;
  /// Edge position inside the firing pixel (edge_run_model.h): each attributed event is moved
  /// from its pixel centre to where the pixel's log level, integrated from its events, puts the
  /// edge, towards the segment's bright side (learned online from event polarities and the
  /// edge's normal motion). Off: the constant `edge_offset_px` (the mean of that offset; events
  /// of an edge lie on its dark side on average).
  bool edge_run_model = true;
  double contrast_threshold = 0;    ///< the sensor's contrast threshold C (log intensity); 0: learned from the run lengths
  double contrast_threshold_prior = 0.3; ///< C used until it is learned (0: the constant edge_offset_px until then)
  int contrast_learning_runs = 1000; ///< completed runs (of >= 3 events) before the learned C replaces the prior
  double edge_contrast_ratio = 9.0; ///< bright / dark intensity across the tracked edges (black print on white paper: ~9)
  double edge_offset_px = 0.15;     ///< constant offset (no run model, or until C is learned); 0: pixel centres
  /// Buffered events are dropped once their projected segment has moved this far (along its
  /// normal, at the event) since they were inserted: buffers then span a bounded image motion,
  /// long when the edge is slow, short when fast. 0: off (thesis: count only).
  double buffer_motion_px = 0.5;
  /// Damping while part of the map is outside the image (fewer, shorter lines constrain the
  /// pose); `estimator.damping` otherwise. Updated at every quality check.
  double damping_partial_view = 1.0;
  int buffer_size = 40;              ///< events per segment buffer (thesis: 8; with the motion bound, 40 measured most accurate, BENCHMARKS.md)
  int init_check_interval = 200;     ///< voted events between detection attempts while initialising
  double init_min_check_period_s = 0.005;  ///< and at least this much event time between attempts (bounds the CPU at high rates)
  int init_min_events = 100;         ///< voted events before the first detection attempt
  int init_refine_events = 400;      ///< latest window events used to refine the initial pose (point-to-line)
  double init_border_margin_px = 3.0; ///< detected segments this close to an image border along it are ignored
  double init_min_coverage = 0.6;   ///< each projected side's visible length must be this much covered by window events
  int init_confirmations = 1;          ///< a detection is accepted when this many of the last 4 detections agree with it
  double init_confirm_position_ratio = 0.1;   ///< agreement: position difference / distance
  double init_confirm_angle_deg = 8.0;        ///< agreement: orientation difference
  double init_max_inside_ratio = 0.3; ///< window events well inside the polygon / events on its sides, upper bound
  // Tracking-quality monitoring.
  int quality_check_interval = 512;  ///< events between quality checks while tracking
  int min_visible_segments = 3;      ///< fewer visible (>= min_visible_length_px inside the image) -> lost
  double min_visible_length_px = 12.0;
  double max_mean_residual_px = 1.5; ///< mean |point-to-line| distance over the buffers above this -> lost
  double min_attributed_ratio = 0.02;///< attributed / all events in a check interval below this -> lost
  double min_depth_m = 0.05;         ///< map points closer (or behind) -> lost
};

/// Validate parameters; returns an empty string when fine, else a message naming the parameter.
std::string validateParams(const LineTrackerParams& params);

struct TrackerStats
{
  uint64_t events = 0;              ///< events processed
  uint64_t events_outside_sensor = 0;
  uint64_t events_attributed = 0;   ///< events attributed to at least one segment
  uint64_t pose_updates = 0;
  uint64_t initializations = 0;     ///< successful (re-)initialisations, the first included
  uint64_t reinitializations = 0;   ///< successful initialisations after a loss
  uint64_t losses = 0;
};

class LineTracker
{
public:
  /// Throws std::invalid_argument when the parameters are invalid (message names the parameter).
  LineTracker(const dvs_calibration::CameraModel& camera, const LineMap& map,
              const LineTrackerParams& params = LineTrackerParams());

  /// Process one event. Returns true when the pose was updated (or initialised) by it.
  bool processEvent(const dvs_driver::Event& event);

  TrackerState state() const { return state_; }
  const CameraPose& pose() const { return pose_; }
  const TrackerStats& stats() const { return stats_; }
  /// Why the track was last lost ("" if never).
  const std::string& lastLossReason() const { return last_loss_reason_; }
  /// Time (ns) of the event that produced the last (re-)initialisation.
  int64_t lastInitTimeNs() const { return last_init_ns_; }
  const std::vector<ProjectedSegment>& projectedSegments() const { return projected_; }
  const std::vector<SegmentBuffer>& buffers() const { return buffers_; }
  const LineMap& map() const { return map_; }
  const LineTrackerParams& params() const { return params_; }
  const PinholeK& intrinsics() const { return k_; }
  /// Where events lie inside their pixels (threshold in use, learning statistics).
  const EdgeRunModel& edgeModel() const { return edge_model_; }
  /// The image polygon of the last successful initialisation (ideal pixels).
  const ImagePolygon& lastInitPolygon() const { return init_polygon_; }

  /// Start tracking from a known pose (skips the Hough initialisation); buffers are seeded.
  void setPose(const CameraPose& pose);
  /// Forget everything and initialise again.
  void reset();
  /// Mean |point-to-line| distance (px) over all buffered points of visible segments.
  double meanResidualPx() const;

private:
  bool processInitializing(const Eigen::Vector2d& p, const dvs_driver::Event& e);
  bool tryInitialize();
  CameraPose refineWithWindowEvents(const CameraPose& initial) const;
  /// Smallest fraction, over the visible map segments, of 3 px cells along the segment holding
  /// a window event within the attribution distance.
  double minSideCoverage(const CameraPose& pose) const;
  void startTracking(const CameraPose& pose);
  void projectSegments(bool update_visibility);
  void relinearize(int segment);
  void updatePose(int changed[2], int num_changed);
  /// The event position moved `edge_offset` px towards segment `i`'s learned bright side
  /// (updates the dark-side evidence).
  Eigen::Vector2d edgeCorrected(const Eigen::Vector2d& p, bool polarity, int i, double edge_offset);
  /// Drop the buffered events of segment `i` its projection has moved away from (motion bound).
  void expireStaleEvents(int i);
  void checkQuality();
  void updateDamping();
  void declareLost(const std::string& reason);

  dvs_calibration::CameraModel camera_;
  LineMap map_;
  LineTrackerParams params_;
  PinholeK k_;
  HoughLineDetector hough_;
  TrackerState state_ = TrackerState::kInitializing;
  CameraPose pose_;
  TrackerStats stats_;
  std::string last_loss_reason_;
  int64_t last_init_ns_ = 0;
  int64_t now_ns_ = 0;
  int voted_since_check_ = 0;
  int64_t last_check_ns_ = std::numeric_limits<int64_t>::min() / 2;
  ImagePolygon init_polygon_;
  std::vector<CameraPose> recent_inits_;  // the last detections awaiting confirmation

  std::vector<ProjectedSegment> projected_;
  std::vector<SegmentBuffer> buffers_;
  /// Which side of an edge is dark: evidence = sum over attributed events of polarity (+-1) x the
  /// normal displacement, at the event, of the projected line since the segment's previous event.
  /// Pooled per polygon (> 0: dark inside; segments of a polygon with a uniform inside share it,
  /// so edges that have barely moved yet are corrected consistently); per segment for segments
  /// in no polygon (> 0: dark along +normal).
  std::vector<double> dark_side_score_;     ///< per polygon, then per segment (index polygons + segment)
  std::vector<int> segment_polygon_;        ///< first polygon holding the segment, -1 if none
  std::vector<ProjectedSegment> last_projection_;  ///< the segment's projection at its previous event
  std::vector<SegmentNormalEquations> equations_;
  EdgeRunModel edge_model_;
  Vector6d x_accumulated_ = Vector6d::Zero();
  double damping_ = 0;  ///< in use: estimator.damping, or damping_partial_view while part of the map is out of view
  int round_robin_ = 0;
  uint64_t check_events_ = 0, check_attributed_ = 0;
  uint64_t updates_since_normalize_ = 0;
};
}  // namespace dvs_line_tracker
