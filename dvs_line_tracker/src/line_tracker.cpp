#include <dvs_line_tracker/line_tracker.h>

#include <algorithm>
#include <cmath>
#include <sstream>
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

std::string validateParams(const LineTrackerParams& p)
{
  std::ostringstream err;
  auto positive = [&](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v))
      err << name << " must be positive (got " << v << "); ";
  };
  positive(p.hough.angle_bin_deg, "hough_angle_bin_deg");
  if (p.hough.angle_bin_deg > 90)
    err << "hough_angle_bin_deg must be <= 90; ";
  positive(p.hough.radius_bin_px, "hough_radius_bin_px");
  positive(p.hough.vote_threshold, "hough_threshold");
  positive(p.hough.attribution_distance_px, "hough_attribution_distance_px");
  positive(p.hough.max_gap_px, "segment_max_gap_px");
  positive(p.hough.min_segment_length_px, "segment_min_length_px");
  positive(p.hough.min_segment_events, "segment_min_events");
  positive(p.hough.window_events, "init_window_events");
  positive(p.hough.neighbour_filter_events, "init_neighbour_filter_events");
  if (p.hough.neighbour_filter_min < 1 || p.hough.neighbour_filter_min > 8)
    err << "init_neighbour_filter_min must be in [1, 8]; ";
  if (!(p.polygon.min_turn_angle_deg >= 0 && p.polygon.min_turn_angle_deg < p.polygon.max_turn_angle_deg &&
        p.polygon.max_turn_angle_deg <= 180))
    err << "polygon_min_angle_deg / polygon_max_angle_deg must satisfy 0 <= min < max <= 180; ";
  positive(p.polygon.corner_proximity_ratio, "polygon_corner_proximity_ratio");
  positive(p.polygon.min_side_px, "polygon_min_side_px");
  positive(p.init.max_reprojection_rms_px, "init_max_reprojection_px");
  positive(p.attribution.max_orthogonal_px, "max_orthogonal_distance_px");
  if (!(p.attribution.max_parallel_px >= 0))
    err << "max_parallel_distance_px must be >= 0; ";
  if (p.buffer_size < 2 || p.buffer_size > 1024)
    err << "buffer_size must be in [2, 1024] (got " << p.buffer_size << "); ";
  positive(p.init_check_interval, "init_check_interval");
  if (!(p.init_min_check_period_s >= 0))
    err << "init_min_check_period must be >= 0; ";
  if (p.init_min_events < 0)
    err << "init_min_events must be >= 0; ";
  positive(p.quality_check_interval, "quality_check_interval");
  if (p.min_visible_segments < 2)
    err << "min_visible_segments must be >= 2 (6-DoF needs at least 3 lines of a polygon); ";
  positive(p.max_mean_residual_px, "max_mean_residual_px");
  if (!(p.min_attributed_ratio >= 0 && p.min_attributed_ratio < 1))
    err << "min_attributed_ratio must be in [0, 1); ";
  if (!(p.estimator.damping >= 0))
    err << "damping must be >= 0; ";
  if (!(p.damping_partial_view >= 0))
    err << "damping_partial_view must be >= 0; ";
  positive(p.estimator.huber_px, "huber_px");
  if (p.estimator.full_iterations < 1)
    err << "full_iterations must be >= 1; ";
  if (!(p.edge_offset_px >= 0 && p.edge_offset_px < p.attribution.max_orthogonal_px))
    err << "edge_offset_px must be in [0, max_orthogonal_distance_px) (got " << p.edge_offset_px << "); ";
  if (!(p.contrast_threshold >= 0 && p.contrast_threshold <= 2))
    err << "contrast_threshold must be in [0, 2] (0: learned; got " << p.contrast_threshold << "); ";
  if (!(p.contrast_threshold_prior >= 0 && p.contrast_threshold_prior <= 2))
    err << "contrast_threshold_prior must be in [0, 2] (0: constant offset until learned; got " << p.contrast_threshold_prior << "); ";
  if (p.contrast_learning_runs < 1)
    err << "contrast_learning_runs must be >= 1; ";
  if (!(p.edge_contrast_ratio > 1 && std::isfinite(p.edge_contrast_ratio)))
    err << "edge_contrast_ratio must be > 1 (got " << p.edge_contrast_ratio << "); ";
  if (!(p.buffer_motion_px >= 0 && std::isfinite(p.buffer_motion_px)))
    err << "buffer_motion_px must be >= 0 (0: off; got " << p.buffer_motion_px << "); ";
  if (p.estimator.extra_relinearizations < 0)
    err << "extra_relinearizations must be >= 0; ";
  return err.str();
}

namespace
{
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
}  // namespace

LineTracker::LineTracker(const dvs_calibration::CameraModel& camera, const LineMap& map,
                         const LineTrackerParams& params)
  : camera_(camera)
  , map_(map)
  , params_(params)
  , hough_(camera.width(), camera.height(), params.hough)
  , edge_model_(camera.width(), camera.height(), edgeModelParams(params))
{
  const std::string err = validateParams(params);
  if (!err.empty())
    throw std::invalid_argument("invalid tracker parameters: " + err);
  if (map.segments.empty() || map.polygons.empty())
    throw std::invalid_argument("the line map needs segments and at least one closed polygon");
  const auto& in = camera.intrinsics();
  k_.fx = in.fx;
  k_.fy = in.fy;
  k_.cx = in.cx;
  k_.cy = in.cy;
  const size_t n = map.segments.size();
  projected_.resize(n);
  buffers_.assign(n, SegmentBuffer(params.buffer_size));
  equations_.resize(n);
  dark_side_score_.assign(map.polygons.size() + n, 0.0);
  segment_polygon_.assign(n, -1);
  for (size_t j = map.polygons.size(); j-- > 0;)
    for (int id : map.polygons[j].segment_ids)
      segment_polygon_[id] = static_cast<int>(j);
  last_projection_.resize(n);
}

void LineTracker::reset()
{
  hough_.reset();
  state_ = TrackerState::kInitializing;
  stats_ = TrackerStats();
  last_loss_reason_.clear();
  voted_since_check_ = 0;
  for (auto& b : buffers_)
    b.clear();
  std::fill(dark_side_score_.begin(), dark_side_score_.end(), 0.0);
}

bool LineTracker::processEvent(const dvs_driver::Event& e)
{
  ++stats_.events;
  now_ns_ = e.t_ns;
  if (e.x >= camera_.width() || e.y >= camera_.height())
  {
    ++stats_.events_outside_sensor;
    return false;
  }
  const Eigen::Vector2d p = camera_.undistortedPixelLut(e.x, e.y).cast<double>();
  const double edge_offset = edge_model_.update(e.x, e.y, e.polarity);
  if (state_ != TrackerState::kTracking)
    return processInitializing(p, e);

  ++check_events_;
  int segs[2];
  const int n = attributeEvent(p, projected_.data(), static_cast<int>(projected_.size()), params_.attribution, segs);
  bool updated = false;
  if (n > 0)
  {
    ++stats_.events_attributed;
    ++check_attributed_;
    for (int i = 0; i < n; ++i)
      buffers_[segs[i]].insert(edgeCorrected(p, e.polarity, segs[i], edge_offset), projected_[segs[i]],
                               params_.attribution.max_orthogonal_px, params_.attribution.max_parallel_px,
                               params_.buffer_motion_px > 0 ? params_.buffer_motion_px : 1e300, params_.estimator.huber_px);
    updatePose(segs, n);
    updated = true;
  }
  if (check_events_ >= static_cast<uint64_t>(params_.quality_check_interval))
    checkQuality();
  return updated && state_ == TrackerState::kTracking;
}

bool LineTracker::processInitializing(const Eigen::Vector2d& p, const dvs_driver::Event& e)
{
  if (!hough_.addEvent(static_cast<float>(p.x()), static_cast<float>(p.y()), e.x, e.y, e.t_ns))
    return false;
  ++voted_since_check_;
  if (hough_.numWindowEvents() < params_.init_min_events || voted_since_check_ < params_.init_check_interval ||
      e.t_ns - last_check_ns_ < static_cast<int64_t>(params_.init_min_check_period_s * 1e9))
    return false;
  voted_since_check_ = 0;
  last_check_ns_ = e.t_ns;
  return tryInitialize();
}

bool LineTracker::tryInitialize()
{
  std::vector<ImageSegment> segments = hough_.detectSegments();
  // Segments along the image border are the borders of accumulated event bands (an edge that
  // leaves the image), not edges of the scene.
  const double m = params_.init_border_margin_px, w = camera_.width() - 1.0, h = camera_.height() - 1.0;
  auto along_border = [&](const ImageSegment& sg) {
    auto near = [&](double a, double b, double border) { return std::abs(a - border) < m && std::abs(b - border) < m; };
    return near(sg.p0.x(), sg.p1.x(), 0.0) || near(sg.p0.x(), sg.p1.x(), w) || near(sg.p0.y(), sg.p1.y(), 0.0) ||
           near(sg.p0.y(), sg.p1.y(), h);
  };
  segments.erase(std::remove_if(segments.begin(), segments.end(), along_border), segments.end());
  std::vector<int> side_counts;
  for (const auto& poly : map_.polygons)
    if (std::find(side_counts.begin(), side_counts.end(), static_cast<int>(poly.segment_ids.size())) ==
        side_counts.end())
      side_counts.push_back(static_cast<int>(poly.segment_ids.size()));
  for (int sides : side_counts)
    for (const ImagePolygon& polygon : findPolygons(segments, sides, params_.polygon, 8))
  {
    bool cut_by_border = false;
    for (const auto& c : polygon.corners)
      cut_by_border |= c.x() < m || c.y() < m || c.x() > w - m || c.y() > h - m;
    if (cut_by_border)
      continue;
    InitialPose init;
    if (!estimateInitialPose(polygon.corners, map_, k_, params_.init, init))
      continue;
    if (params_.init_refine_events > 0)
      init.pose = refineWithWindowEvents(init.pose);
    // Validate: every visible side must be backed by events along most of its length (a
    // polygon assembled from noise or from unrelated edges is not).
    if (minSideCoverage(init.pose) < params_.init_min_coverage)
      continue;
    // Two detections in a row must agree (a false polygon from smeared or partial edges rarely
    // repeats itself consistently).
    if (params_.init_confirmations > 0)
    {
      int agreeing = 0;
      for (const auto& earlier : recent_inits_)
        agreeing += positionError(earlier, init.pose) <
                            params_.init_confirm_position_ratio * init.pose.positionWorld().norm() &&
                        orientationError(earlier, init.pose) < params_.init_confirm_angle_deg * M_PI / 180
                    ? 1
                    : 0;
      recent_inits_.push_back(init.pose);
      if (recent_inits_.size() > 4)
        recent_inits_.erase(recent_inits_.begin());
      if (agreeing < params_.init_confirmations)
        return false;
    }
    recent_inits_.clear();
    const bool was_lost = state_ == TrackerState::kLost;
    startTracking(init.pose);
    if (state_ != TrackerState::kTracking)
      continue;
    init_polygon_ = polygon;
    last_init_ns_ = now_ns_;
    if (was_lost)
      ++stats_.reinitializations;
    ++stats_.initializations;
    ++stats_.pose_updates;
    return true;
  }
  return false;
}

CameraPose LineTracker::refineWithWindowEvents(const CameraPose& initial) const
{
  // The latest window events near the projected map segments pull the corner-based pose onto
  // all edge events (point-to-line Gauss-Newton, re-attributing every iteration).
  std::vector<Eigen::Vector2d> points = hough_.windowPoints();
  if (static_cast<int>(points.size()) > params_.init_refine_events)
    points.erase(points.begin(), points.end() - params_.init_refine_events);
  const size_t n = map_.segments.size();
  CameraPose pose = initial;
  std::vector<SegmentNormalEquations> eqs(n);
  std::vector<ProjectedSegment> proj(n);
  for (int it = 0; it < 8; ++it)
  {
    std::vector<SegmentBuffer> buffers(n, SegmentBuffer(static_cast<int>(points.size())));
    for (size_t i = 0; i < n; ++i)
    {
      const Eigen::Vector3d a = pose.toCamera(map_.segments[i].p0_world), b = pose.toCamera(map_.segments[i].p1_world);
      proj[i].visible = a.z() > params_.min_depth_m && b.z() > params_.min_depth_m;
      if (proj[i].visible)
        proj[i].set(k_.project(a), k_.project(b));
    }
    for (const auto& p : points)
    {
      int segs[2];
      const int m = attributeEvent(p, proj.data(), static_cast<int>(n), params_.attribution, segs);
      for (int j = 0; j < m; ++j)
        buffers[segs[j]].insert(p, proj[segs[j]], 1e300, 1e300, 1e300, params_.estimator.huber_px);
    }
    int used = 0;
    for (size_t i = 0; i < n; ++i)
    {
      eqs[i].active = buffers[i].size() >= 5 &&
                      linearizeSegment(k_, pose, map_.segments[i].p0_world, map_.segments[i].p1_world, buffers[i], eqs[i]);
      eqs[i].x_lin.setZero();
      used += eqs[i].active ? 1 : 0;
    }
    if (used < params_.min_visible_segments)
      return initial;
    Vector6d delta;
    if (!solveStep(eqs.data(), static_cast<int>(n), Vector6d::Zero(), 1e-6, delta))
      return initial;
    pose.applyIncrement(delta);
    if (delta.norm() < 1e-9)
      break;
  }
  // Keep the refinement only if it stays close to the corner solution (a sanity bound).
  if (positionError(pose, initial) > 0.3 * initial.positionWorld().norm() || !pose.t_cam_world.allFinite())
    return initial;
  return pose;
}

double LineTracker::minSideCoverage(const CameraPose& pose) const
{
  // The polygon search needs every side, so a genuine detection sees every map corner of the
  // polygon inside the image (off its border): polygons cut by the border are not trusted.
  for (const auto& poly : map_.polygons)
    for (const auto& c : poly.corners_world)
    {
      const Eigen::Vector3d pc = pose.toCamera(c);
      if (pc.z() <= params_.min_depth_m)
        return 0.0;
      const Eigen::Vector2d px = k_.project(pc);
      const double margin = params_.init_border_margin_px;
      if (px.x() < margin || px.y() < margin || px.x() > camera_.width() - 1 - margin ||
          px.y() > camera_.height() - 1 - margin)
        return 0.0;
    }
  const std::vector<Eigen::Vector2d> points = hough_.windowPoints();
  constexpr double kCell = 3.0;
  double worst = 1.0;
  int visible = 0;
  std::vector<char> filled;
  for (const auto& seg : map_.segments)
  {
    const Eigen::Vector3d a = pose.toCamera(seg.p0_world), b = pose.toCamera(seg.p1_world);
    if (a.z() <= params_.min_depth_m || b.z() <= params_.min_depth_m)
      return 0.0;
    Eigen::Vector2d ca, cb;
    const double len = clippedLength(k_.project(a), k_.project(b), -0.5, -0.5, camera_.width() - 0.5,
                                     camera_.height() - 0.5, &ca, &cb);
    if (len < params_.min_visible_length_px)
      continue;
    ++visible;
    ProjectedSegment ps;
    ps.set(ca, cb);
    const int cells = std::max(1, static_cast<int>(len / kCell));
    filled.assign(cells, 0);
    for (const auto& p : points)
    {
      if (ps.orthogonalDistance(p) > params_.attribution.max_orthogonal_px)
        continue;
      const double t = ps.dir.dot(p - ps.a);
      if (t < 0 || t >= len)
        continue;
      filled[std::min(cells - 1, static_cast<int>(t / len * cells))] = 1;
    }
    int n = 0;
    for (char f : filled)
      n += f;
    worst = std::min(worst, static_cast<double>(n) / cells);
  }
  if (visible < params_.min_visible_segments)
    return 0.0;
  // A polygon's inside is quiet; a "polygon" cut out of a band of smeared events is not.
  for (const auto& poly : map_.polygons)
  {
    std::vector<ProjectedSegment> sides;
    for (size_t i = 0; i < poly.corners_world.size(); ++i)
    {
      ProjectedSegment ps;
      ps.set(k_.project(pose.toCamera(poly.corners_world[i])),
             k_.project(pose.toCamera(poly.corners_world[(i + 1) % poly.corners_world.size()])));
      sides.push_back(ps);
    }
    int on_sides = 0, inside = 0;
    for (const auto& p : points)
    {
      double nearest = 1e300;
      int sign_pos = 0, sign_neg = 0;
      for (const auto& sd : sides)
      {
        const double d = sd.normal.dot(p - sd.a);
        (d >= 0 ? sign_pos : sign_neg)++;
        if (sd.parallelDistance(p) < 0)
          nearest = std::min(nearest, std::abs(d));
      }
      if (nearest <= params_.attribution.max_orthogonal_px)
        ++on_sides;
      else if ((sign_pos == 0 || sign_neg == 0) && nearest > 2 * params_.attribution.max_orthogonal_px)
        ++inside;
    }
    if (inside > params_.init_max_inside_ratio * std::max(on_sides, 1))
      return 0.0;
  }
  return worst;
}

void LineTracker::setPose(const CameraPose& pose)
{
  last_init_ns_ = now_ns_;
  startTracking(pose);
}

void LineTracker::startTracking(const CameraPose& pose)
{
  pose_ = pose;
  damping_ = params_.estimator.damping;
  x_accumulated_.setZero();
  projectSegments(true);
  last_projection_ = projected_;
  int visible = 0;
  for (size_t i = 0; i < projected_.size(); ++i)
  {
    buffers_[i].clear();
    const ProjectedSegment& s = projected_[i];
    if (!s.visible)
      continue;
    ++visible;
    // Seed the buffer with points spread along the visible part of the projected segment.
    Eigen::Vector2d ca, cb;
    clippedLength(s.a, s.b, -0.5, -0.5, camera_.width() - 0.5, camera_.height() - 0.5, &ca, &cb);
    const int k = buffers_[i].capacity();
    for (int j = 0; j < k; ++j)
      buffers_[i].insert(ca + (cb - ca) * ((j + 0.5) / k), s);
  }
  for (size_t i = 0; i < projected_.size(); ++i)
    relinearize(static_cast<int>(i));
  check_events_ = check_attributed_ = 0;
  state_ = visible >= params_.min_visible_segments ? TrackerState::kTracking : state_;
  if (state_ != TrackerState::kTracking)
    hough_.reset();
}

void LineTracker::projectSegments(bool update_visibility)
{
  const double w = camera_.width(), h = camera_.height();
  for (size_t i = 0; i < map_.segments.size(); ++i)
  {
    ProjectedSegment& s = projected_[i];
    const Eigen::Vector3d pc0 = pose_.toCamera(map_.segments[i].p0_world);
    const Eigen::Vector3d pc1 = pose_.toCamera(map_.segments[i].p1_world);
    s.in_front = pc0.z() > params_.min_depth_m && pc1.z() > params_.min_depth_m;
    if (!s.in_front)
    {
      s.visible = false;
      s.visible_length = 0;
      continue;
    }
    s.set(k_.project(pc0), k_.project(pc1));
    if (update_visibility)
    {
      s.visible_length = clippedLength(s.a, s.b, -0.5, -0.5, w - 0.5, h - 0.5);
      s.visible = s.visible_length >= params_.min_visible_length_px;
    }
  }
}

Eigen::Vector2d LineTracker::edgeCorrected(const Eigen::Vector2d& p, bool polarity, int i, double edge_offset)
{
  // ON events: the bright side gains pixels, i.e. the edge moves towards its dark side; OFF: the
  // other way. Pose jitter is uncorrelated with polarity and averages out of the evidence.
  const ProjectedSegment& s = projected_[i];
  ProjectedSegment& last = last_projection_[i];
  // Displacement of the line along +normal at the event: its signed distance then minus now.
  const double moved = last.normal.dot(p - last.a) - s.normal.dot(p - s.a);
  last.a = s.a;
  last.normal = s.normal;
  const int poly = segment_polygon_[i];
  double inside_along_normal = 1.0;  // +1: the polygon's inside is along +normal (segments in no polygon: +1)
  int slot = static_cast<int>(map_.polygons.size()) + i;
  if (poly >= 0)
  {
    // Convex polygons: the inside is the side of the projected centroid of the corners.
    const auto& ids = map_.polygons[poly].segment_ids;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (int id : ids)
      centre += projected_[id].a + projected_[id].b;
    centre /= 2.0 * ids.size();
    inside_along_normal = s.normal.dot(centre - s.a) >= 0 ? 1.0 : -1.0;
    slot = poly;
  }
  double& score = dark_side_score_[slot];
  score += (polarity ? 1.0 : -1.0) * moved * inside_along_normal;
  // Trusted once the edges have moved about a pixel consistently.
  constexpr double kMinScore = 1.0;
  if (std::abs(score) < kMinScore)
    return p;
  const double dark_along_normal = score > 0 ? inside_along_normal : -inside_along_normal;
  return p - dark_along_normal * edge_offset * s.normal;
}

void LineTracker::relinearize(int i)
{
  SegmentNormalEquations& eq = equations_[i];
  eq.active = projected_[i].visible &&
              linearizeSegment(k_, pose_, map_.segments[i].p0_world, map_.segments[i].p1_world, buffers_[i], eq);
  eq.x_lin = x_accumulated_;
}

void LineTracker::updatePose(int changed[2], int num_changed)
{
  const int n = static_cast<int>(equations_.size());
  const auto& ep = params_.estimator;
  if (ep.solver == SolverType::kIncremental)
  {
    for (int c = 0; c < num_changed; ++c)
      relinearize(changed[c]);
    for (int r = 0; r < ep.extra_relinearizations && n > 1; ++r)
    {
      round_robin_ = (round_robin_ + 1) % n;
      // Segments without events of their own lose their stale events here.
      expireStaleEvents(round_robin_);
      relinearize(round_robin_);
    }
    Vector6d delta;
    if (solveStep(equations_.data(), n, x_accumulated_, damping_, delta))
    {
      pose_.applyIncrement(delta);
      x_accumulated_ += delta;
    }
  }
  else
  {
    for (int it = 0; it < ep.full_iterations; ++it)
    {
      for (int i = 0; i < n; ++i)
        relinearize(i);
      Vector6d delta;
      if (!solveStep(equations_.data(), n, x_accumulated_, damping_, delta))
        break;
      pose_.applyIncrement(delta);
      x_accumulated_ += delta;
      projectSegments(false);
      if (delta.squaredNorm() < 1e-16)
        break;
    }
  }
  if (++updates_since_normalize_ >= 4096)
  {
    pose_.normalize();
    updates_since_normalize_ = 0;
  }
  // Visibility (clipping) is refreshed by the quality check; per event only the projection.
  projectSegments(false);
  ++stats_.pose_updates;
}

double LineTracker::meanResidualPx() const
{
  double sum = 0;
  int count = 0;
  for (size_t i = 0; i < projected_.size(); ++i)
  {
    if (!projected_[i].visible)
      continue;
    for (int j = 0; j < buffers_[i].size(); ++j)
    {
      sum += projected_[i].orthogonalDistance(buffers_[i].point(j));
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

void LineTracker::expireStaleEvents(int i)
{
  if (params_.buffer_motion_px > 0 && projected_[i].in_front)
    buffers_[i].expire(projected_[i], params_.buffer_motion_px);
}

void LineTracker::updateDamping()
{
  // Part of the map outside the image (or behind the camera): fewer and shorter lines constrain
  // the pose, so its weakly observable directions get the stronger damping. Uses the visible
  // lengths of the last projectSegments(true).
  bool partial = false;
  for (const auto& s : projected_)
    partial |= !s.in_front || s.visible_length < s.length - 1.0;
  damping_ = partial ? std::max(params_.estimator.damping, params_.damping_partial_view) : params_.estimator.damping;
}

void LineTracker::checkQuality()
{
  projectSegments(true);
  // Segments that moved without producing events (e.g. an edge leaving the view) would keep
  // their stale events: drop them here too, not only when the segment receives an event.
  for (size_t i = 0; i < buffers_.size(); ++i)
    expireStaleEvents(static_cast<int>(i));
  int visible = 0;
  for (const auto& s : projected_)
    visible += s.visible ? 1 : 0;
  updateDamping();
  const double ratio = check_events_ > 0 ? static_cast<double>(check_attributed_) / check_events_ : 1.0;
  check_events_ = check_attributed_ = 0;
  if (!pose_.R_cam_world.allFinite() || !pose_.t_cam_world.allFinite())
    return declareLost("the pose is not finite");
  for (const auto& s : projected_)
    if (!s.in_front)
      return declareLost("part of the map is behind the camera");
  if (visible < params_.min_visible_segments)
    return declareLost("segments left the view (" + std::to_string(visible) + " visible)");
  const double residual = meanResidualPx();
  if (residual > params_.max_mean_residual_px)
    return declareLost("residuals grew (mean " + std::to_string(residual) + " px)");
  if (ratio < params_.min_attributed_ratio)
    return declareLost("attribution collapsed (" + std::to_string(100.0 * ratio) + " % of events attributed)");
}

void LineTracker::declareLost(const std::string& reason)
{
  recent_inits_.clear();
  state_ = TrackerState::kLost;
  last_loss_reason_ = reason;
  ++stats_.losses;
  hough_.reset();
  voted_since_check_ = 0;
}
}  // namespace dvs_line_tracker
