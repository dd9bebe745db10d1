#include <dvs_screen_sim/scene_renderer.h>

#include <algorithm>
#include <cmath>

namespace dvs_screen_sim
{
namespace
{
constexpr double kZNear = 1e-3;  // [m] polygons are clipped to z >= kZNear in the camera frame
constexpr size_t kMaxConvexVertices = 60;  // polygons up to this many vertices use the fast clipper
constexpr double kEdgePieceLength = 2.0;   // [px] visible edges are sampled at least this densely

inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return a.x() * b.y() - a.y() * b.x();
}

double shoelace(const std::vector<Eigen::Vector2d>& p)
{
  double a = 0;
  for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++)
    a += cross2(p[j], p[i]);
  return 0.5 * a;
}

/// Liang-Barsky: clip segment a-b to the box; false when nothing remains.
bool clipSegmentToBox(Eigen::Vector2d& a, Eigen::Vector2d& b, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi)
{
  double t0 = 0, t1 = 1;
  const Eigen::Vector2d d = b - a;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() - lo.x(), hi.x() - a.x(), a.y() - lo.y(), hi.y() - a.y()};
  for (int i = 0; i < 4; ++i)
  {
    if (p[i] == 0)
    {
      if (q[i] < 0)
        return false;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0)
      t0 = std::max(t0, r);
    else
      t1 = std::min(t1, r);
    if (t0 > t1)
      return false;
  }
  const Eigen::Vector2d a0 = a;
  a = a0 + t0 * d;
  b = a0 + t1 * d;
  return true;
}
}  // namespace

SceneRenderer::SceneRenderer(const dvs_calibration::CameraModel& camera, const Scene& scene)
  : camera_(camera), scene_(scene), width_(camera.width()), height_(camera.height())
{
  if (scene_.parents().size() != scene_.polygons.size())
    scene_.finalize();
  corners_.resize(static_cast<size_t>(width_ + 1) * (height_ + 1));
  view_lo_ = Eigen::Vector2d::Constant(1e300);
  view_hi_ = Eigen::Vector2d::Constant(-1e300);
  for (int cy = 0; cy <= height_; ++cy)
    for (int cx = 0; cx <= width_; ++cx)
    {
      const Eigen::Vector2d xn = camera_.pixelToUndistortedNormalized(Eigen::Vector2d(cx - 0.5, cy - 0.5));
      corners_[static_cast<size_t>(cy) * (width_ + 1) + cx] = xn;
      view_lo_ = view_lo_.cwiseMin(xn);
      view_hi_ = view_hi_.cwiseMax(xn);
    }
  const auto& k = camera_.intrinsics();
  px_per_normalized_ = std::max(k.fx, k.fy);
  const double margin = 2.0 / std::min(k.fx, k.fy);
  view_lo_.array() -= margin;
  view_hi_.array() += margin;
  projected_.resize(scene_.polygons.size());
  polygon_convex_.assign(scene_.polygons.size(), false);
  for (size_t k = 0; k < scene_.polygons.size(); ++k)
  {
    // Convex on the wall = convex in the image (projective maps, near clipping = intersection
    // with a half-space). The fast clipper's buffers hold up to kMaxConvexVertices + 4 points.
    const auto& v = scene_.polygons[k].vertices;
    const size_t n = v.size();
    bool pos = false, neg = false;
    for (size_t i = 0; i < n; ++i)
    {
      const double c = cross2(v[(i + 1) % n] - v[i], v[(i + 2) % n] - v[(i + 1) % n]);
      pos |= c > 1e-15;
      neg |= c < -1e-15;
    }
    polygon_convex_[k] = !(pos && neg) && n + 1 <= kMaxConvexVertices;
  }
  size_t max_vertices = 0;
  for (const auto& p : scene_.polygons)
    max_vertices = std::max(max_vertices, p.vertices.size());
  scratch_a_.reserve(2 * max_vertices + 16);
  scratch_b_.reserve(2 * max_vertices + 16);
  for (auto& pp : projected_)
    pp.v.reserve(2 * max_vertices + 4);
}

Eigen::Vector2d SceneRenderer::toSensorPixel(const Eigen::Vector2d& xn) const
{
  return camera_.normalizedToPixel(camera_.distortNormalized(xn));
}

void SceneRenderer::projectWallPolygon(const std::vector<Eigen::Vector2d>& wall, const Eigen::Matrix3d& R_cam_world,
                                       const Eigen::Vector3d& t_cam_world, std::vector<Eigen::Vector2d>& out) const
{
  // Clip against the near plane in 3D (Sutherland-Hodgman, one plane) and project.
  out.clear();
  const size_t n = wall.size();
  auto cam = [&](size_t i) -> Eigen::Vector3d {
    const auto& v = wall[i % n];
    return R_cam_world * Eigen::Vector3d(v.x(), v.y(), 0.0) + t_cam_world;
  };
  Eigen::Vector3d prev = cam(n - 1);
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector3d cur = cam(i);
    const bool cin = cur.z() >= kZNear, pin = prev.z() >= kZNear;
    if (cin != pin)
    {
      const double u = (kZNear - prev.z()) / (cur.z() - prev.z());
      const Eigen::Vector3d x = prev + u * (cur - prev);
      out.emplace_back(x.x() / x.z(), x.y() / x.z());
    }
    if (cin)
      out.emplace_back(cur.x() / cur.z(), cur.y() / cur.z());
    prev = cur;
  }
}

void SceneRenderer::addVisibleEdgePoints(const std::vector<Eigen::Vector2d>& outline)
{
  // Edge points inside the view, every <= kEdgePieceLength px, with their wall points (for motion bounds and
  // the band of pixels the edges touch).
  const Eigen::Vector3d& c = p_world_camera_;
  for (size_t i = 0; i < outline.size(); ++i)
  {
    Eigen::Vector2d a = outline[i], b = outline[(i + 1) % outline.size()];
    if (!clipSegmentToBox(a, b, view_lo_, view_hi_))
      continue;
    const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() * px_per_normalized_ / kEdgePieceLength)));
    for (int j = 0; j <= pieces; ++j)
    {
      const Eigen::Vector2d xn = a + (b - a) * (static_cast<double>(j) / pieces);
      const Eigen::Vector3d d_world = R_world_camera_ * Eigen::Vector3d(xn.x(), xn.y(), 1.0);
      if (std::abs(d_world.z()) < 1e-12)
        continue;
      const double s = -c.z() / d_world.z();
      if (s <= 0)
        continue;
      visible_edge_points_world_.push_back(c + s * d_world);
      visible_edge_points_px_.push_back(toSensorPixel(xn));
    }
    // Separator between edges: a NaN pixel marks "start a new polyline".
    visible_edge_points_world_.push_back(Eigen::Vector3d::Constant(std::nan("")));
    visible_edge_points_px_.push_back(Eigen::Vector2d::Constant(std::nan("")));
  }
}

void SceneRenderer::setState(const Pose& T_world_camera, double t)
{
  // Images change the picture everywhere when the camera moves, their gain changes or their
  // content is refreshed; otherwise their pixels keep their intensities.
  images_changed_ = !has_state_ || T_world_camera.t_camera_world != T_world_camera_.t_camera_world ||
                    T_world_camera.R_camera_world != T_world_camera_.R_camera_world;
  has_state_ = true;
  content_transition_ = 0;
  T_world_camera_ = T_world_camera;
  p_world_camera_ = T_world_camera.p_world_camera();
  time_ = t;
  background_ = scene_.background_reflectance;
  const Eigen::Matrix3d& R_cam_world = T_world_camera.R_camera_world;
  const Eigen::Vector3d& t_cam_world = T_world_camera.t_camera_world;
  R_world_camera_ = R_cam_world.transpose();
  visible_edge_points_world_.clear();
  visible_edge_points_px_.clear();
  for (size_t k = 0; k < scene_.polygons.size(); ++k)
  {
    auto& pp = projected_[k];
    pp.delta = scene_.polygonIntensity(k, t) - scene_.underIntensity(k, t);
    projectWallPolygon(scene_.polygons[k].vertices, R_cam_world, t_cam_world, pp.v);
    pp.valid = pp.v.size() >= 3;
    if (!pp.valid)
      continue;
    pp.lo = pp.hi = pp.v[0];
    for (const auto& v : pp.v)
    {
      pp.lo = pp.lo.cwiseMin(v);
      pp.hi = pp.hi.cwiseMax(v);
    }
    pp.orientation = shoelace(pp.v) >= 0 ? 1.0 : -1.0;
    pp.convex = polygon_convex_[k] && pp.v.size() <= kMaxConvexVertices;
    addVisibleEdgePoints(pp.v);
  }
  if (scene_.images.empty())
    return;
  projected_images_.resize(scene_.images.size());
  for (size_t k = 0; k < scene_.images.size(); ++k)
  {
    auto& im = scene_.images[k];
    auto& pi = projected_images_[k];
    const double gain = im.gainAt(t);
    if (gain != pi.gain)
      images_changed_ = true;
    pi.gain = gain;
    if (im.update_period > 0)
    {
      const auto frame = static_cast<int64_t>(std::floor(t / im.update_period + 1e-9));
      if (frame != pi.frame)
      {
        im.update(frame, im.texels);
        if (im.texels.size() != static_cast<size_t>(im.width) * im.height)
          throw SceneError("scene image '" + im.name + "': update changed the number of texels");
        pi.frame = frame;
        images_changed_ = true;
        content_transition_ = std::max(content_transition_, im.response_time);
      }
    }
    const Eigen::Vector2d tl = im.top_left;
    const std::vector<Eigen::Vector2d> rect = {
        tl, tl + Eigen::Vector2d(im.size.x(), 0), tl + Eigen::Vector2d(im.size.x(), -im.size.y()),
        tl + Eigen::Vector2d(0, -im.size.y())};
    projectWallPolygon(rect, R_cam_world, t_cam_world, pi.v);
    pi.valid = pi.v.size() >= 3;
    if (!pi.valid)
      continue;
    pi.lo = pi.hi = pi.v[0];
    for (const auto& v : pi.v)
    {
      pi.lo = pi.lo.cwiseMin(v);
      pi.hi = pi.hi.cwiseMax(v);
    }
    addVisibleEdgePoints(pi.v);
  }
  // Wall points of every pixel corner (NaN when the ray misses the wall).
  corner_wall_.resize(corners_.size());
  const Eigen::Vector3d& c = p_world_camera_;
  for (size_t i = 0; i < corners_.size(); ++i)
  {
    const Eigen::Vector3d d = R_world_camera_ * Eigen::Vector3d(corners_[i].x(), corners_[i].y(), 1.0);
    const double s = std::abs(d.z()) < 1e-12 ? -1.0 : -c.z() / d.z();
    corner_wall_[i] = s > 0 ? Eigen::Vector2d(c.x() + s * d.x(), c.y() + s * d.y())
                            : Eigen::Vector2d::Constant(std::nan(""));
  }
}

double SceneRenderer::imageIntensity(size_t k, int x, int y, double under) const
{
  const SceneImage& im = scene_.images[k];
  const size_t w1 = static_cast<size_t>(width_) + 1;
  const Eigen::Vector2d* w[4] = {&corner_wall_[static_cast<size_t>(y) * w1 + x],
                                 &corner_wall_[static_cast<size_t>(y) * w1 + x + 1],
                                 &corner_wall_[static_cast<size_t>(y + 1) * w1 + x + 1],
                                 &corner_wall_[static_cast<size_t>(y + 1) * w1 + x]};
  Eigen::Vector2d tex[4];
  for (int i = 0; i < 4; ++i)
  {
    if (std::isnan(w[i]->x()))
      return under;
    tex[i] = Eigen::Vector2d((w[i]->x() - im.top_left.x()) / im.size.x() * im.width,
                             (im.top_left.y() - w[i]->y()) / im.size.y() * im.height);
  }
  double extent = 0;
  for (int i = 0; i < 4; ++i)
    extent = std::max(extent, (tex[(i + 1) & 3] - tex[i]).norm());
  const int n = std::clamp(static_cast<int>(std::ceil(2.0 * extent)), 2, 16);
  double sum = 0;
  int inside = 0;
  for (int j = 0; j < n; ++j)
  {
    const double tv = (j + 0.5) / n;
    const Eigen::Vector2d left = tex[0] + tv * (tex[3] - tex[0]);
    const Eigen::Vector2d right = tex[1] + tv * (tex[2] - tex[1]);
    for (int i = 0; i < n; ++i)
    {
      const Eigen::Vector2d p = left + ((i + 0.5) / n) * (right - left);
      if (p.x() < 0 || p.y() < 0 || p.x() >= im.width || p.y() >= im.height)
        continue;
      sum += im.texels[static_cast<size_t>(p.y()) * im.width + static_cast<size_t>(p.x())];
      ++inside;
    }
  }
  const double nn = static_cast<double>(n) * n;
  return under * (1.0 - inside / nn) + projected_images_[k].gain * sum / nn;
}

double SceneRenderer::clippedArea(const Eigen::Vector2d* quad, double orientation,
                                  const std::vector<Eigen::Vector2d>& poly) const
{
  std::vector<Eigen::Vector2d>* in = &scratch_a_;
  std::vector<Eigen::Vector2d>* out = &scratch_b_;
  in->assign(poly.begin(), poly.end());
  for (int e = 0; e < 4 && !in->empty(); ++e)
  {
    const Eigen::Vector2d& c0 = quad[e];
    const Eigen::Vector2d d = quad[(e + 1) & 3] - c0;
    out->clear();
    const size_t n = in->size();
    Eigen::Vector2d prev = (*in)[n - 1];
    double sprev = orientation * cross2(d, prev - c0);
    for (size_t i = 0; i < n; ++i)
    {
      const Eigen::Vector2d cur = (*in)[i];
      const double scur = orientation * cross2(d, cur - c0);
      if ((scur >= 0) != (sprev >= 0))
      {
        const double u = sprev / (sprev - scur);
        out->push_back(prev + u * (cur - prev));
      }
      if (scur >= 0)
        out->push_back(cur);
      prev = cur;
      sprev = scur;
    }
    std::swap(in, out);
  }
  if (in->size() < 3)
    return 0.0;
  return std::abs(shoelace(*in));
}

double SceneRenderer::convexClippedArea(const Eigen::Vector2d* quad, const ProjectedPolygon& pp)
{
  Eigen::Vector2d buf_a[kMaxConvexVertices + 8], buf_b[kMaxConvexVertices + 8];
  Eigen::Vector2d* in = buf_a;
  Eigen::Vector2d* out = buf_b;
  int n = 4;
  for (int i = 0; i < 4; ++i)
    in[i] = quad[i];
  double side[kMaxConvexVertices + 8];
  const size_t m = pp.v.size();
  for (size_t e = 0; e < m; ++e)
  {
    const Eigen::Vector2d& a = pp.v[e];
    const Eigen::Vector2d d = pp.v[(e + 1) % m] - a;
    bool any_out = false, any_in = false;
    for (int i = 0; i < n; ++i)
    {
      side[i] = pp.orientation * cross2(d, in[i] - a);
      any_out |= side[i] < 0;
      any_in |= side[i] > 0;
    }
    if (!any_out)
      continue;  // the edge does not cut the footprint
    if (!any_in)
      return 0.0;  // the footprint is outside this edge's half-plane
    int k = 0;
    for (int i = 0, j = n - 1; i < n; j = i++)
    {
      const bool cin = side[i] >= 0, pin = side[j] >= 0;
      if (cin != pin)
        out[k++] = in[j] + (side[j] / (side[j] - side[i])) * (in[i] - in[j]);
      if (cin)
        out[k++] = in[i];
    }
    std::swap(in, out);
    n = k;
    if (n < 3)
      return 0.0;
  }
  double area = 0;
  for (int i = 0, j = n - 1; i < n; j = i++)
    area += cross2(in[j], in[i]);
  return std::abs(0.5 * area);
}

double SceneRenderer::pixelIntensity(int x, int y) const
{
  const Eigen::Vector2d quad[4] = {cornerNormalized(x, y), cornerNormalized(x + 1, y), cornerNormalized(x + 1, y + 1),
                                   cornerNormalized(x, y + 1)};
  const Eigen::Vector2d lo = quad[0].cwiseMin(quad[1]).cwiseMin(quad[2]).cwiseMin(quad[3]);
  const Eigen::Vector2d hi = quad[0].cwiseMax(quad[1]).cwiseMax(quad[2]).cwiseMax(quad[3]);
  const double signed_area =
      0.5 * (cross2(quad[0], quad[1]) + cross2(quad[1], quad[2]) + cross2(quad[2], quad[3]) + cross2(quad[3], quad[0]));
  const double orientation = signed_area >= 0 ? 1.0 : -1.0;
  const double area = std::abs(signed_area);
  double intensity = background_;
  for (const auto& pp : projected_)
  {
    if (!pp.valid || pp.delta == 0.0 || pp.hi.x() < lo.x() || pp.lo.x() > hi.x() || pp.hi.y() < lo.y() ||
        pp.lo.y() > hi.y())
      continue;
    const double covered = pp.convex ? convexClippedArea(quad, pp) : clippedArea(quad, orientation, pp.v);
    intensity += pp.delta * std::min(1.0, covered / area);
  }
  for (size_t k = 0; k < projected_images_.size(); ++k)
  {
    const auto& pi = projected_images_[k];
    if (!pi.valid || pi.hi.x() < lo.x() || pi.lo.x() > hi.x() || pi.hi.y() < lo.y() || pi.lo.y() > hi.y())
      continue;
    intensity = imageIntensity(k, x, y, intensity);
  }
  return std::clamp(intensity, 0.0, 1.0);
}

void SceneRenderer::renderImage(std::vector<double>& image) const
{
  image.resize(static_cast<size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      image[static_cast<size_t>(y) * width_ + x] = pixelIntensity(x, y);
}

void SceneRenderer::appendEdgePixels(std::vector<int32_t>& pixels, std::vector<uint32_t>& marks, uint32_t mark) const
{
  const double r = band_radius;
  const double r2 = r * r;
  for (size_t i = 1; i < visible_edge_points_px_.size(); ++i)
  {
    const Eigen::Vector2d& a = visible_edge_points_px_[i - 1];
    const Eigen::Vector2d& b = visible_edge_points_px_[i];
    if (std::isnan(a.x()) || std::isnan(b.x()))
      continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min(a.x(), b.x()) - r)));
    const int x1 = std::min(width_ - 1, static_cast<int>(std::ceil(std::max(a.x(), b.x()) + r)));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min(a.y(), b.y()) - r)));
    const int y1 = std::min(height_ - 1, static_cast<int>(std::ceil(std::max(a.y(), b.y()) + r)));
    const Eigen::Vector2d d = b - a;
    const double len2 = d.squaredNorm();
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
      {
        const int32_t idx = y * width_ + x;
        if (marks[static_cast<size_t>(idx)] == mark)
          continue;
        const Eigen::Vector2d p(x - a.x(), y - a.y());
        const double u = len2 > 0 ? std::clamp(p.dot(d) / len2, 0.0, 1.0) : 0.0;
        if ((p - u * d).squaredNorm() <= r2)
        {
          marks[static_cast<size_t>(idx)] = mark;
          pixels.push_back(idx);
        }
      }
  }
}

double SceneRenderer::maxImageMotion(const Pose& T_world_camera_other) const
{
  double max_motion = 0;
  for (size_t i = 0; i < visible_edge_points_world_.size(); ++i)
  {
    const Eigen::Vector3d& pw = visible_edge_points_world_[i];
    if (std::isnan(pw.x()))
      continue;
    Eigen::Vector2d px;
    if (!camera_.project(T_world_camera_other.toCamera(pw), px))
      return 1e6;
    max_motion = std::max(max_motion, (px - visible_edge_points_px_[i]).norm());
  }
  return std::min(max_motion, 1e6);
}
}  // namespace dvs_screen_sim
