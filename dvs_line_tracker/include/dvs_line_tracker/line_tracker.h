#pragma once
// The event-based 6-DoF line tracker (thesis ch. 4) as a short state machine over its parts:
// TrackerInitializer (Hough / polygon search / pose initialisation while INITIALIZING or LOST),
// EventUpdater (per-event attribution and pose update while TRACKING), LossMonitor (periodic
// quality checks), an optional StatePropagator (motion between events), all on one
// EstimatorState. Where each event's position inside its pixel lies: EdgeRunModel.
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/event.h>
#include <dvs_line_tracker/edge_run_model.h>
#include <dvs_line_tracker/estimator_state.h>
#include <dvs_line_tracker/event_updater.h>
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/loss_monitor.h>
#include <dvs_line_tracker/motion_lag.h>
#include <dvs_line_tracker/state_propagator.h>
#include <dvs_line_tracker/tracker_initializer.h>
#include <dvs_line_tracker/tracker_params.h>

#include <cstdint>
#include <memory>
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

struct TrackerStats
{
  uint64_t events = 0;              ///< events processed
  uint64_t events_outside_sensor = 0;
  uint64_t events_attributed = 0;   ///< events attributed to at least one segment
  uint64_t pose_updates = 0;
  uint64_t initializations = 0;     ///< successful (re-)initialisations, the first included
  uint64_t reinitializations = 0;   ///< successful initialisations after a loss
  uint64_t losses = 0;
  uint64_t time_jumps = 0;          ///< restarts because event time went backwards
  uint64_t gaps_bridged = 0;        ///< event-free gaps longer than max_event_gap carried by the propagator (IMU)
  /// Partial views held (partial_view_grace_s: only two sides meeting at a corner in view; the
  /// estimate goes on, no pose is reported), those of them that ended with a third side back in
  /// view (the rest ended in a loss), and the event time spent in them.
  uint64_t partial_views_held = 0;
  uint64_t partial_views_resumed = 0;
  double partial_view_held_s = 0;
};

class LineTracker
{
public:
  /// Throws std::invalid_argument when the parameters are invalid (message names the parameter)
  /// or the map has no closed polygon.
  LineTracker(const dvs_calibration::CameraModel& camera, const LineMap& map,
              const LineTrackerParams& params = LineTrackerParams());
  LineTracker(const LineTracker&) = delete;
  LineTracker& operator=(const LineTracker&) = delete;

  /// Process one event. Returns true when the pose was updated (or initialised) by it.
  bool processEvent(const dvs_driver::Event& event);

  TrackerState state() const { return status_; }
  /// Tracking, but only a corner of the map is in view: the track is held (partial_view_grace_s)
  /// and no pose is reported until a third side comes back or the track is lost.
  bool partialViewHeld() const { return status_ == TrackerState::kTracking && hold_since_ns_ >= 0; }
  const Pose& pose() const { return estimator_.pose; }
  const TrackerStats& stats() const { return stats_; }
  /// Why the track was last lost ("" if never).
  const std::string& lastLossReason() const { return last_loss_reason_; }
  /// Time (ns) of the event that produced the last (re-)initialisation.
  int64_t lastInitTimeNs() const { return last_init_ns_; }
  const std::vector<ProjectedSegment>& projectedSegments() const { return estimator_.projected; }
  const std::vector<SegmentBuffer>& buffers() const { return estimator_.buffers; }
  const EstimatorState& estimatorState() const { return estimator_; }
  const LineMap& map() const { return geometry_.map; }
  const dvs_calibration::CameraModel& camera() const { return camera_; }
  const LineTrackerParams& params() const { return params_; }
  const PinholeK& intrinsics() const { return geometry_.k; }
  /// Where events lie inside their pixels (threshold in use, learning statistics).
  const EdgeRunModel& edgeModel() const { return edge_model_; }
  /// The image polygon of the last successful initialisation (ideal pixels).
  const ImagePolygon& lastInitPolygon() const { return initializer_.lastPolygon(); }
  /// The initialiser's counters: why there is no pose yet.
  const InitializerStats& initializerStats() const { return initializer_.stats(); }

  /// Motion between events (e.g. an IMU); nullptr: the pose is held between events.
  void setPropagator(std::shared_ptr<StatePropagator> propagator) { propagator_ = std::move(propagator); }
  /// Start tracking from a known pose (skips the Hough initialisation); buffers are seeded.
  void setPose(const Pose& pose);
  /// Forget everything (every part) and initialise again.
  void reset();
  /// The pose covariance of vision alone (rotation error in camera axes, then position in the
  /// world): the buffered events' Gauss-Newton covariance x kVisionOnlyCovarianceScale, plus the
  /// lag of a moving camera behind the buffers (motion_lag.h).
  Matrix6d visionOnlyPoseCovariance() const;
  /// That lag term alone (zero while the motion is not known): the IMU filter's odometry adds it
  /// too, since the vision updates it is corrected by trail the camera as much.
  Matrix6d motionLagCovariance() const;
  /// Mean |point-to-line| distance (px) over all buffered points of visible segments.
  double meanResidualPx() const { return dvs_line_tracker::meanResidualPx(estimator_); }

private:
  bool startTracking(const Pose& pose);
  /// Event time went back: forget everything time-dependent, keep the counters, say why.
  void restartAfterTimeJump(int64_t t_ns);
  void declareLost(const std::string& reason);
  /// A partial view that was held ends at `t_ns` (counted in the stats).
  void endPartialView(int64_t t_ns, bool resumed);

  /// Feeds the remembered events since `since_ns` through the per-event update (init_catch_up).
  void catchUp(int64_t since_ns);

  /// The latest events while not tracking, for catchUp (a ring of kCatchUpCapacity).
  struct RecentEvent
  {
    int64_t t_ns;
    Eigen::Vector2f p;  ///< ideal position
    float edge_offset;
    bool polarity;
  };
  std::vector<RecentEvent> recent_;
  size_t recent_head_ = 0, recent_count_ = 0;

  dvs_calibration::CameraModel camera_;
  LineTrackerParams params_;
  TrackingGeometry geometry_;
  EstimatorState estimator_;
  EdgeRunModel edge_model_;
  TrackerInitializer initializer_;
  EventUpdater updater_;
  LossMonitor monitor_;
  Pose held_pose_;  ///< the pose when a partial view began (partial_view_grace_s)
  int64_t hold_since_ns_ = -1;  ///< event time the partial view held now began (-1: none)
  MotionLag lag_;
  std::shared_ptr<StatePropagator> propagator_;

  TrackerState status_ = TrackerState::kInitializing;
  TrackerStats stats_;
  std::string last_loss_reason_;
  int64_t last_init_ns_ = 0;
  int64_t now_ns_ = 0;
  bool have_time_ = false;  ///< now_ns_ holds an event's time
  int64_t max_backwards_ns_ = 0;
  int64_t max_gap_ns_ = 0;
};
}  // namespace dvs_line_tracker
