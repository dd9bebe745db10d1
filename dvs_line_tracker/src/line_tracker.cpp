#include <dvs_line_tracker/line_tracker.h>

#include <dvs_line_tracker/body_odometry.h>

#include <algorithm>
#include <stdexcept>

namespace dvs_line_tracker
{
const char* toString(TrackerState state)
{
  switch (state)
  {
    case TrackerState::kInitializing:
      return "INITIALIZING";
    case TrackerState::kTracking:
      return "TRACKING";
    case TrackerState::kLost:
      return "LOST";
  }
  return "?";
}

namespace
{
/// Events remembered while not tracking, for the catch-up at the start (init_catch_up): more
/// than a 640x480 sensor's refinement window (1,732 voted events) and the noise filtered
/// between them; when the window reaches further back, the catch-up starts at the oldest kept.
constexpr size_t kCatchUpCapacity = 4096;

const LineTrackerParams& validated(const LineTrackerParams& params, const LineMap& map)
{
  const std::string err = validateParams(params);
  if (!err.empty())
    throw std::invalid_argument("invalid tracker parameters: " + err);
  if (map.segments.empty() || map.polygons.empty())
    throw std::invalid_argument("the line map needs segments and at least one closed polygon");
  return params;
}

TrackingGeometry makeGeometry(const dvs_calibration::CameraModel& camera, const LineMap& map,
                              const LineTrackerParams& params)
{
  TrackingGeometry g;
  g.map = map;
  g.indexSharedEndpoints();
  const auto& in = camera.intrinsics();
  g.k.fx = in.fx;
  g.k.fy = in.fy;
  g.k.cx = in.cx;
  g.k.cy = in.cy;
  g.width = camera.width();
  g.height = camera.height();
  // The undistorted image reaches furthest from the centre somewhere on the sensor's border.
  const Eigen::Vector2d centre((g.width - 1) / 2.0, (g.height - 1) / 2.0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; x += (y == 0 || y == g.height - 1) ? 1 : std::max(1, g.width - 1))
      g.ideal_radius_px = std::max(g.ideal_radius_px, (camera.undistortedPixelLut(x, y).cast<double>() - centre).norm());
  g.min_depth_m = params.min_depth_m;
  g.min_visible_length_px = params.min_visible_length_px;
  return g;
}

EdgeRunModelParams edgeModelParams(const LineTrackerParams& p)
{
  EdgeRunModelParams m;
  m.enabled = p.edge_run_model;
  m.contrast_threshold = p.contrast_threshold;
  m.min_learning_runs = p.contrast_learning_runs;
  m.prior_threshold = p.contrast_threshold_prior;
  m.edge_contrast_ratio = p.edge_contrast_ratio;
  m.constant_offset_px = p.edge_offset_px;
  return m;
}

std::vector<std::vector<int>> polygonSegments(const LineMap& map)
{
  std::vector<std::vector<int>> out;
  for (const auto& poly : map.polygons)
    out.push_back(poly.segment_ids);
  return out;
}
}  // namespace

LineTracker::LineTracker(const dvs_calibration::CameraModel& camera, const LineMap& map,
                         const LineTrackerParams& params)
  : camera_(camera)
  , params_(validated(params, map))
  , geometry_(makeGeometry(camera, map, params_))
  , edge_model_(camera.width(), camera.height(), edgeModelParams(params_))
  , initializer_(geometry_, params_)
  , updater_(geometry_, params_)
  , monitor_(params_, camera.width(), camera.height(), initializer_.scaledNeighbourHorizon(params_.loss_neighbour_events),
             static_cast<int>(map.segments.size()), polygonSegments(geometry_.map))
{
  estimator_.resize(map.segments.size(), params_.buffer_size);
  if (params_.init_catch_up)
    recent_.resize(kCatchUpCapacity);
  max_backwards_ns_ = static_cast<int64_t>(params_.max_time_backwards_s * 1e9);
  max_gap_ns_ = static_cast<int64_t>(params_.max_event_gap_s * 1e9);
}

void LineTracker::reset()
{
  initializer_.reset();
  updater_.reset();
  monitor_.restart();
  hold_since_ns_ = -1;
  edge_model_ = EdgeRunModel(camera_.width(), camera_.height(), edgeModelParams(params_));
  estimator_.resize(geometry_.map.segments.size(), params_.buffer_size);
  status_ = TrackerState::kInitializing;
  stats_ = TrackerStats();
  last_loss_reason_.clear();
  last_init_ns_ = 0;
  recent_count_ = 0;
  have_time_ = false;
}

void LineTracker::restartAfterTimeJump(int64_t t_ns)
{
  const double back_s = (now_ns_ - t_ns) * 1e-9;
  endPartialView(now_ns_, false);
  TrackerStats kept = stats_;
  reset();
  stats_ = kept;
  ++stats_.time_jumps;
  last_loss_reason_ = "event time went back by " + std::to_string(back_s) + " s (a replayed recording?): restarted";
}

bool LineTracker::processEvent(const dvs_driver::Event& e)
{
  bool bridged = false;
  if (have_time_ && e.t_ns < now_ns_ - max_backwards_ns_)
    restartAfterTimeJump(e.t_ns);
  else if (status_ == TrackerState::kTracking && max_gap_ns_ > 0 && e.t_ns - now_ns_ > max_gap_ns_)
  {
    // An event-free gap: a healthy IMU carries the pose across it; without one the pose is stale.
    bridged = propagator_ && propagator_->active(now_ns_) && propagator_->active(e.t_ns) &&
              e.t_ns - now_ns_ <= propagator_->maxBridgeNs();
    if (!bridged)
      declareLost("no events for " + std::to_string((e.t_ns - now_ns_) * 1e-9) + " s: the pose is stale");
  }
  ++stats_.events;
  now_ns_ = e.t_ns;
  have_time_ = true;
  if (e.x >= camera_.width() || e.y >= camera_.height())
  {
    ++stats_.events_outside_sensor;
    return false;
  }
  const Eigen::Vector2d p = camera_.undistortedPixelLut(e.x, e.y).cast<double>();
  const double edge_offset = edge_model_.update(e.x, e.y, e.polarity);
  if (status_ != TrackerState::kTracking)
  {
    const bool was_lost = status_ == TrackerState::kLost;
    if (!recent_.empty())
    {
      recent_[recent_head_] = {e.t_ns, p.cast<float>(), static_cast<float>(edge_offset), e.polarity != 0};
      recent_head_ = (recent_head_ + 1) % recent_.size();
      recent_count_ = std::min(recent_count_ + 1, recent_.size());
    }
    if (!initializer_.addEvent(p, e, [this](const Pose& pose) { return startTracking(pose); }))
      return false;
    catchUp(initializer_.refineWindowStartNs());
    last_init_ns_ = now_ns_;
    stats_.reinitializations += was_lost ? 1 : 0;
    ++stats_.initializations;
    ++stats_.pose_updates;
    return true;
  }

  if (propagator_)
    propagator_->propagate(estimator_, e.t_ns);
  if (bridged)
  {
    // The buffers hold the edges where they were before the gap: start them again at the
    // predicted pose (not a loss, not an initialisation).
    propagator_->noteGapBridged();
    ++stats_.gaps_bridged;
    monitor_.reset();
    if (updater_.start(estimator_, estimator_.pose) < params_.min_visible_segments)
    {
      declareLost("after an event gap bridged by the IMU too few map segments are in view");
      return false;
    }
  }
  int attributed_to[2];
  // An IMU that moves the pose between events: every event solved (a held one would be compared
  // with the projection of a pose the prediction has left; with solves held, the fused IMU's
  // 2.3 m flips were 9 % less accurate, BENCHMARKS.md).
  const bool predicted = propagator_ && propagator_->active(e.t_ns);
  const bool updated = updater_.update(estimator_, p, e.polarity, edge_offset, e.t_ns, attributed_to, !predicted);
  monitor_.countEvent(updated, e.x, e.y, attributed_to, &p, &estimator_.projected);
  if (monitor_.due())
  {
    updater_.refresh(estimator_, lag_.attributedRate());
    const bool was_held = monitor_.partialViewHeld();
    const std::string reason = monitor_.check(estimator_, e.t_ns);
    if (!reason.empty())
    {
      // A partial view that outlasted partial_view_grace_s: the pose before it is the prior
      // (the estimate drifted in the directions two lines leave free).
      if (was_held)
        estimator_.pose = held_pose_;
      declareLost(reason);
    }
    else if (!was_held && monitor_.partialViewHeld())
    {
      held_pose_ = estimator_.pose;
      hold_since_ns_ = e.t_ns;
      ++stats_.partial_views_held;
    }
    else if (was_held && !monitor_.partialViewHeld())
      endPartialView(e.t_ns, true);
  }
  // While only a corner is in view (partial_view_grace_s) the estimate goes on but reports no
  // pose: it resumes when a third side comes back, or the track is lost when none does.
  const bool held = partialViewHeld();
  if (updated)
  {
    ++stats_.events_attributed;
    if (!held)
      ++stats_.pose_updates;
  }
  if (status_ == TrackerState::kTracking)
    lag_.sample(e.t_ns, estimator_.pose, stats_.events_attributed);
  return updated && status_ == TrackerState::kTracking && !held;
}

void LineTracker::catchUp(int64_t since_ns)
{
  const size_t n = recent_.size();
  for (size_t i = 0; i < recent_count_; ++i)
  {
    const RecentEvent& r = recent_[(recent_head_ + n - recent_count_ + i) % n];
    if (r.t_ns >= since_ns)
      updater_.update(estimator_, r.p.cast<double>(), r.polarity, r.edge_offset, r.t_ns);
  }
  recent_count_ = 0;
}

void LineTracker::setPose(const Pose& pose)
{
  last_init_ns_ = now_ns_;
  if (!startTracking(pose))
    initializer_.restart();
}

bool LineTracker::startTracking(const Pose& pose)
{
  const int visible = updater_.start(estimator_, pose);
  endPartialView(now_ns_, false);
  monitor_.restart();
  if (visible < params_.min_visible_segments)
    return false;
  status_ = TrackerState::kTracking;
  lag_.reset();
  if (propagator_)
    propagator_->restart(estimator_, now_ns_);
  return true;
}

Matrix6d LineTracker::motionLagCovariance() const
{
  return lag_.covariance(estimator_.visibleSegments(), params_.buffer_size);
}

Matrix6d LineTracker::visionOnlyPoseCovariance() const
{
  return visionPoseCovariance(estimator_) * kVisionOnlyCovarianceScale + motionLagCovariance();
}

void LineTracker::endPartialView(int64_t t_ns, bool resumed)
{
  if (hold_since_ns_ < 0)
    return;
  stats_.partial_view_held_s += (t_ns - hold_since_ns_) * 1e-9;
  stats_.partial_views_resumed += resumed ? 1 : 0;
  hold_since_ns_ = -1;
}

void LineTracker::declareLost(const std::string& reason)
{
  endPartialView(now_ns_, false);
  status_ = TrackerState::kLost;
  last_loss_reason_ = reason;
  ++stats_.losses;
  initializer_.restart();
  initializer_.setPrior(estimator_.pose, now_ns_);
}
}  // namespace dvs_line_tracker
