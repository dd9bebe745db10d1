#include <dvs_screen_sim/screen_loop/line_grid_check.h>

#include <cmath>
#include <limits>
#include <map>

namespace dvs_screen_sim
{
namespace screen_loop
{
std::vector<WorldLine> lineGrid(int nx, int ny, double spacing, const Eigen::Vector2d& centre)
{
  std::vector<WorldLine> lines;
  const double hw = 0.5 * (nx - 1) * spacing, hh = 0.5 * (ny - 1) * spacing;
  for (int i = 0; i < nx; ++i)
  {
    const double x = centre.x() - hw + i * spacing;
    lines.push_back({{x, centre.y() - hh, 0.0}, {x, centre.y() + hh, 0.0}});
  }
  for (int j = 0; j < ny; ++j)
  {
    const double y = centre.y() - hh + j * spacing;
    lines.push_back({{centre.x() - hw, y, 0.0}, {centre.x() + hw, y, 0.0}});
  }
  return lines;
}

Scene lineGridScene(int nx, int ny, double spacing, double width, const IntensityModulation& modulation,
                    double background, const Eigen::Vector2d& centre)
{
  Scene scene;
  scene.background_reflectance = background;
  const double hw = 0.5 * (nx - 1) * spacing, hh = 0.5 * (ny - 1) * spacing, r = 0.5 * width;
  auto rect = [&](const std::string& name, double x0, double y0, double x1, double y1) {
    ScenePolygon p;
    p.name = name;
    p.vertices = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    p.modulation = modulation;
    p.reflectance = modulation.high;
    scene.polygons.push_back(p);
  };
  // Vertical lines over the whole height (incl. the horizontal lines' half width).
  for (int i = 0; i < nx; ++i)
  {
    const double x = centre.x() - hw + i * spacing;
    rect("v" + std::to_string(i), x - r, centre.y() - hh - r, x + r, centre.y() + hh + r);
  }
  // Horizontal lines between the vertical ones.
  for (int j = 0; j < ny; ++j)
  {
    const double y = centre.y() - hh + j * spacing;
    for (int i = 0; i + 1 < nx; ++i)
    {
      const double x0 = centre.x() - hw + i * spacing + r, x1 = centre.x() - hw + (i + 1) * spacing - r;
      if (x1 > x0)
        rect("h" + std::to_string(j) + "_" + std::to_string(i), x0, y - r, x1, y + r);
    }
  }
  scene.finalize();
  return scene;
}

std::vector<ImageSegment> expectedImageLines(const dvs_calibration::CameraModel& camera, const Pose& T_world_camera,
                                             const std::vector<WorldLine>& lines)
{
  std::vector<ImageSegment> out;
  const double z_min = 0.01;
  for (const auto& l : lines)
  {
    Eigen::Vector3d a = T_world_camera.toCamera(l.a), b = T_world_camera.toCamera(l.b);
    if (a.z() < z_min && b.z() < z_min)
      continue;
    if (a.z() < z_min)
      a = a + (b - a) * ((z_min - a.z()) / (b.z() - a.z()));
    if (b.z() < z_min)
      b = b + (a - b) * ((z_min - b.z()) / (a.z() - b.z()));
    ImageSegment s;
    camera.projectIdeal(a, s.a);
    camera.projectIdeal(b, s.b);
    out.push_back(s);
  }
  return out;
}

LineDistanceStats eventLineDistances(const dvs_driver::EventVector& events, const dvs_calibration::CameraModel& camera,
                                     const std::vector<ImageSegment>& expected, double max_distance, double chunk_px,
                                     size_t min_chunk_events)
{
  LineDistanceStats st;
  st.events_total = events.size();
  // (line, chunk) -> (sum of signed offsets, count)
  std::map<std::pair<size_t, long>, std::pair<double, size_t>> chunks;
  double sum = 0;
  for (const auto& e : events)
  {
    if (!camera.inSensor(e.x, e.y))
      continue;
    const Eigen::Vector2f uf = camera.undistortedPixelLut(e.x, e.y);
    const Eigen::Vector2d p(uf.x(), uf.y());
    double best = std::numeric_limits<double>::infinity(), best_signed = 0, best_along = 0;
    size_t best_line = 0;
    for (size_t k = 0; k < expected.size(); ++k)
    {
      const Eigen::Vector2d d = expected[k].b - expected[k].a;
      const double len2 = d.squaredNorm();
      if (len2 < 1e-12)
        continue;
      const double u = std::clamp((p - expected[k].a).dot(d) / len2, 0.0, 1.0);
      const Eigen::Vector2d q = expected[k].a + u * d;
      const double dist = (p - q).norm();
      if (dist < best)
      {
        best = dist;
        best_line = k;
        const Eigen::Vector2d n(-d.y(), d.x());
        best_signed = (p - expected[k].a).dot(n) / std::sqrt(len2);
        best_along = u * std::sqrt(len2);
      }
    }
    if (!(best <= max_distance))
      continue;
    ++st.events_used;
    sum += best;
    auto& c = chunks[{best_line, static_cast<long>(std::floor(best_along / chunk_px))}];
    c.first += best_signed;
    ++c.second;
  }
  if (st.events_used > 0)
    st.mean_event_distance = sum / st.events_used;
  double off = 0;
  for (const auto& kv : chunks)
  {
    if (kv.second.second < min_chunk_events)
      continue;
    off += std::abs(kv.second.first / kv.second.second);
    ++st.chunks;
  }
  if (st.chunks > 0)
    st.mean_line_offset = off / st.chunks;
  return st;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
