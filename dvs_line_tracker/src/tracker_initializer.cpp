#include <dvs_line_tracker/tracker_initializer.h>

#include <dvs_line_tracker/pose_initializer.h>

#include <algorithm>
#include <cmath>

namespace dvs_line_tracker
{
TrackerInitializer::TrackerInitializer(const TrackingGeometry& geometry, const LineTrackerParams& params)
  : geometry_(geometry), params_(params), hough_(geometry.width, geometry.height, params.hough)
{
  for (const auto& poly : geometry.map.polygons)
    if (std::find(side_counts_.begin(), side_counts_.end(), static_cast<int>(poly.segment_ids.size())) ==
        side_counts_.end())
      side_counts_.push_back(static_cast<int>(poly.segment_ids.size()));
}

void TrackerInitializer::restart()
{
  recent_.clear();
  hough_.reset();
  voted_since_check_ = 0;
}

void TrackerInitializer::reset()
{
  restart();
  last_check_ns_ = std::numeric_limits<int64_t>::min() / 2;
  last_polygon_ = ImagePolygon();
}

bool TrackerInitializer::addEvent(const Eigen::Vector2d& p, const dvs_driver::Event& e, const StartTracking& start)
{
  if (!hough_.addEvent(static_cast<float>(p.x()), static_cast<float>(p.y()), e.x, e.y, e.t_ns))
    return false;
  ++voted_since_check_;
  if (hough_.numWindowEvents() < params_.init_min_events || voted_since_check_ < params_.init_check_interval ||
      e.t_ns - last_check_ns_ < static_cast<int64_t>(params_.init_min_check_period_s * 1e9))
    return false;
  voted_since_check_ = 0;
  last_check_ns_ = e.t_ns;
  return tryInitialize(start);
}

bool TrackerInitializer::alongBorder(const ImageSegment& sg) const
{
  // Segments along the image border are the borders of accumulated event bands (an edge that
  // leaves the image), not edges of the scene.
  const double m = params_.init_border_margin_px, w = geometry_.width - 1.0, h = geometry_.height - 1.0;
  auto near = [&](double a, double b, double border) { return std::abs(a - border) < m && std::abs(b - border) < m; };
  return near(sg.p0.x(), sg.p1.x(), 0.0) || near(sg.p0.x(), sg.p1.x(), w) || near(sg.p0.y(), sg.p1.y(), 0.0) ||
         near(sg.p0.y(), sg.p1.y(), h);
}

bool TrackerInitializer::confirmed(const Pose& pose)
{
  // Two detections in a row must agree (a false polygon from smeared or partial edges rarely
  // repeats itself consistently).
  if (params_.init_confirmations <= 0)
    return true;
  int agreeing = 0;
  for (const auto& earlier : recent_)
    agreeing += positionError(earlier, pose) < params_.init_confirm_position_ratio * pose.p_world_camera().norm() &&
                        orientationError(earlier, pose) < params_.init_confirm_angle_deg * M_PI / 180
                    ? 1
                    : 0;
  recent_.push_back(pose);
  if (recent_.size() > 4)
    recent_.erase(recent_.begin());
  return agreeing >= params_.init_confirmations;
}

bool TrackerInitializer::tryInitialize(const StartTracking& start)
{
  std::vector<ImageSegment> segments = hough_.detectSegments();
  segments.erase(std::remove_if(segments.begin(), segments.end(),
                                [this](const ImageSegment& sg) { return alongBorder(sg); }),
                 segments.end());
  const double m = params_.init_border_margin_px, w = geometry_.width - 1.0, h = geometry_.height - 1.0;
  for (int sides : side_counts_)
    for (const ImagePolygon& polygon : findPolygons(segments, sides, params_.polygon, 8))
    {
      bool cut_by_border = false;
      for (const auto& c : polygon.corners)
        cut_by_border |= c.x() < m || c.y() < m || c.x() > w - m || c.y() > h - m;
      if (cut_by_border)
        continue;
      InitialPose init;
      if (!estimateInitialPose(polygon.corners, geometry_.map, geometry_.k, params_.init, init))
        continue;
      if (params_.init_refine_events > 0)
        init.pose = refineWithWindowEvents(init.pose);
      // Validate: every visible side must be backed by events along most of its length (a
      // polygon assembled from noise or from unrelated edges is not).
      if (minSideCoverage(init.pose) < params_.init_min_coverage)
        continue;
      if (!confirmed(init.pose))
        return false;
      recent_.clear();
      if (!start(init.pose))
      {
        hough_.reset();
        continue;
      }
      last_polygon_ = polygon;
      return true;
    }
  return false;
}

Pose TrackerInitializer::refineWithWindowEvents(const Pose& initial) const
{
  // The latest window events near the projected map segments pull the corner-based pose onto
  // all edge events (point-to-line Gauss-Newton, re-attributing every iteration).
  std::vector<Eigen::Vector2d> points = hough_.windowPoints();
  if (static_cast<int>(points.size()) > params_.init_refine_events)
    points.erase(points.begin(), points.end() - params_.init_refine_events);
  const LineMap& map = geometry_.map;
  const size_t n = map.segments.size();
  Pose pose = initial;
  std::vector<SegmentNormalEquations> eqs(n);
  std::vector<ProjectedSegment> proj(n);
  for (int it = 0; it < 8; ++it)
  {
    std::vector<SegmentBuffer> buffers(n, SegmentBuffer(static_cast<int>(points.size())));
    for (size_t i = 0; i < n; ++i)
    {
      const Eigen::Vector3d a = pose.toCamera(map.segments[i].p0_world), b = pose.toCamera(map.segments[i].p1_world);
      proj[i].visible = a.z() > params_.min_depth_m && b.z() > params_.min_depth_m;
      if (proj[i].visible)
        proj[i].set(geometry_.k.project(a), geometry_.k.project(b));
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
      eqs[i].active = buffers[i].size() >= 5 && linearizeSegment(geometry_.k, pose, map.segments[i].p0_world,
                                                                 map.segments[i].p1_world, buffers[i], eqs[i]);
      eqs[i].x_lin.setZero();
      used += eqs[i].active ? 1 : 0;
    }
    if (used < params_.min_visible_segments)
      return initial;
    Vector6d delta;
    if (!solveStep(eqs.data(), static_cast<int>(n), Vector6d::Zero(), 1e-6, delta))
      return initial;
    pose.applyCameraIncrement(delta);
    if (delta.norm() < 1e-9)
      break;
  }
  // Keep the refinement only if it stays close to the corner solution (a sanity bound).
  if (positionError(pose, initial) > 0.3 * initial.p_world_camera().norm() || !pose.t_camera_world.allFinite())
    return initial;
  return pose;
}

double TrackerInitializer::minSideCoverage(const Pose& pose) const
{
  const LineMap& map = geometry_.map;
  const PinholeK& k = geometry_.k;
  const int width = geometry_.width, height = geometry_.height;
  // The polygon search needs every side, so a genuine detection sees every map corner of the
  // polygon inside the image (off its border): polygons cut by the border are not trusted.
  for (const auto& poly : map.polygons)
    for (const auto& c : poly.corners_world)
    {
      const Eigen::Vector3d pc = pose.toCamera(c);
      if (pc.z() <= params_.min_depth_m)
        return 0.0;
      const Eigen::Vector2d px = k.project(pc);
      const double margin = params_.init_border_margin_px;
      if (px.x() < margin || px.y() < margin || px.x() > width - 1 - margin || px.y() > height - 1 - margin)
        return 0.0;
    }
  const std::vector<Eigen::Vector2d> points = hough_.windowPoints();
  constexpr double kCell = 3.0;
  double worst = 1.0;
  int visible = 0;
  std::vector<char> filled;
  for (const auto& seg : map.segments)
  {
    const Eigen::Vector3d a = pose.toCamera(seg.p0_world), b = pose.toCamera(seg.p1_world);
    if (a.z() <= params_.min_depth_m || b.z() <= params_.min_depth_m)
      return 0.0;
    Eigen::Vector2d ca, cb;
    const double len =
        clippedLength(k.project(a), k.project(b), -0.5, -0.5, width - 0.5, height - 0.5, &ca, &cb);
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
  for (const auto& poly : map.polygons)
  {
    std::vector<ProjectedSegment> sides;
    for (size_t i = 0; i < poly.corners_world.size(); ++i)
    {
      ProjectedSegment ps;
      ps.set(k.project(pose.toCamera(poly.corners_world[i])),
             k.project(pose.toCamera(poly.corners_world[(i + 1) % poly.corners_world.size()])));
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
}  // namespace dvs_line_tracker
