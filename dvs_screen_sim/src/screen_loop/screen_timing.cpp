#include <dvs_screen_sim/screen_loop/screen_timing.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace dvs_screen_sim
{
namespace screen_loop
{
void RefreshPeriodEstimator::addSwapTime(double t)
{
  if (has_last_ && t > last_)
    intervals_.push_back(t - last_);
  last_ = t;
  has_last_ = true;
}

double RefreshPeriodEstimator::period() const
{
  if (intervals_.empty())
    return 0.0;
  std::vector<double> v = intervals_;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(mid), v.end());
  if (v.size() % 2 == 1)
    return v[mid];
  const double hi = v[mid];
  const double lo = *std::max_element(v.begin(), v.begin() + static_cast<long>(mid));
  return 0.5 * (lo + hi);
}

void DvsClockOffset::addPacket(int64_t last_event_ns, int64_t arrival_host_ns)
{
  const int64_t d = last_event_ns - arrival_host_ns;
  offset_ns_ = packets_ == 0 ? d : std::max(offset_ns_, d);
  ++packets_;
}

void TimeScale::validate() const
{
  if (!(factor > 0) || !std::isfinite(factor))
    throw std::invalid_argument("time_scale must be a positive number (got " + std::to_string(factor) + ")");
}

double screenMotionPx(const ProjectionPipeline& pipeline, const Trajectory& trajectory,
                      const std::vector<Eigen::Vector3d>& points, double t, double dt, int w, int h)
{
  const Pose p0 = trajectory.poseAt(t), p1 = trajectory.poseAt(t + dt);
  double worst = 0;
  for (const auto& x : points)
  {
    Eigen::Vector2d a, b;
    if (!pipeline.viewport(p0, x, a) || !pipeline.viewport(p1, x, b))
      continue;
    // Only points on the screen (or close to it) matter.
    if (std::abs(a.x()) > 1.2 || std::abs(a.y()) > 1.2)
      continue;
    worst = std::max(worst, (viewportToWindow(a, w, h) - viewportToWindow(b, w, h)).norm());
  }
  return worst;
}

std::vector<Eigen::Vector3d> motionSamplePoints(const Scene& scene, const std::vector<WorldLine>& lines, double spacing)
{
  std::vector<Eigen::Vector3d> pts;
  auto addEdge = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing)));
    for (int i = 0; i < n; ++i)
      pts.push_back(a + (b - a) * (static_cast<double>(i) / n));
  };
  for (const auto& poly : scene.polygons)
    for (size_t i = 0; i < poly.vertices.size(); ++i)
    {
      const auto& a = poly.vertices[i];
      const auto& b = poly.vertices[(i + 1) % poly.vertices.size()];
      addEdge({a.x(), a.y(), 0.0}, {b.x(), b.y(), 0.0});
    }
  for (const auto& l : lines)
  {
    addEdge(l.a, l.b);
    pts.push_back(l.b);
  }
  return pts;
}

MotionCheck checkApparentMotion(const ProjectionPipeline& pipeline, const Trajectory& trajectory,
                                const std::vector<Eigen::Vector3d>& points, double t0, double t1, double refresh_period,
                                const TimeScale& time_scale, int w, int h)
{
  if (!(refresh_period > 0))
    throw std::invalid_argument("checkApparentMotion: refresh_period must be positive");
  time_scale.validate();
  MotionCheck mc;
  const double dt = refresh_period / time_scale.factor;  // trajectory time per refresh
  for (double t = t0; t < t1; t += dt)
  {
    const double m = screenMotionPx(pipeline, trajectory, points, t, dt, w, h);
    if (m > mc.max_px_per_refresh)
    {
      mc.max_px_per_refresh = m;
      mc.worst_time = t;
    }
  }
  // The motion per refresh scales ~ linearly with 1 / factor.
  mc.suggested_time_scale = std::max(1.0, time_scale.factor * mc.max_px_per_refresh);
  return mc;
}

std::string motionWarning(const MotionCheck& c)
{
  if (c.max_px_per_refresh <= 1.0 + 1e-9)
    return std::string();
  std::ostringstream s;
  s.precision(3);
  s << "apparent motion reaches " << c.max_px_per_refresh << " screen pixels per refresh (at trajectory time "
    << c.worst_time << " s): the screen will blur it (thesis 3.4.2); a time scale of "
    << c.suggested_time_scale
    << " avoids that, but slowing the playback multiplies the DVS's noise per trajectory second by the time scale: "
       "blur of up to ~1 DVS pixel per refresh is acceptable (thesis 6, and dvs_screen_sim's BENCHMARKS.md)";
  return s.str();
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
