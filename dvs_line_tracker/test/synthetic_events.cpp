#include "synthetic_events.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace dvs_line_tracker
{
namespace
{
struct RowSpan
{
  double left = 0, right = -1;  // inside x range (ideal px); empty when right < left
  bool empty() const { return right < left; }
};

// Inside span of a convex image polygon on row y.
RowSpan spanOnRow(const std::vector<Eigen::Vector2d>& poly, double y)
{
  RowSpan s;
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector2d& p = poly[i];
    const Eigen::Vector2d& q = poly[(i + 1) % n];
    if ((p.y() <= y && q.y() > y) || (q.y() <= y && p.y() > y))
    {
      const double x = p.x() + (y - p.y()) * (q.x() - p.x()) / (q.y() - p.y());
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
  if (hi >= lo)
  {
    s.left = lo;
    s.right = hi;
  }
  return s;
}

// Integer pixel range [first, last] whose centres lie inside the span, clipped to the image.
void pixelRange(const RowSpan& s, int width, int& first, int& last)
{
  if (s.empty())
  {
    first = 0;
    last = -1;
    return;
  }
  first = std::max(0, static_cast<int>(std::ceil(s.left)));
  last = std::min(width - 1, static_cast<int>(std::floor(s.right)));
}

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const Eigen::Vector2d d = b - a;
  const double t = std::max(0.0, std::min(1.0, d.dot(p - a) / d.squaredNorm()));
  return (a + t * d - p).norm();
}
}  // namespace

SyntheticSequence generateSyntheticEvents(const LineMap& map, const PoseFunction& trajectory,
                                          const SyntheticEventParams& params)
{
  SyntheticSequence seq;
  std::mt19937_64 rng(params.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const int steps = static_cast<int>(std::ceil(params.duration_s / params.time_step_s));
  const size_t num_polys = map.polygons.size();

  auto project = [&](const Pose& pose, std::vector<std::vector<Eigen::Vector2d>>& out) {
    out.resize(num_polys);
    bool ok = true;
    for (size_t pi = 0; pi < num_polys; ++pi)
    {
      out[pi].clear();
      for (const auto& c : map.polygons[pi].corners_world)
      {
        const Eigen::Vector3d pc = pose.toCamera(c);
        if (pc.z() < 1e-3)
          ok = false;
        out[pi].push_back(params.k.project(pc));
      }
    }
    return ok;
  };

  std::vector<std::vector<Eigen::Vector2d>> prev_poly, cur_poly;
  std::vector<std::vector<RowSpan>> prev_spans(num_polys, std::vector<RowSpan>(params.height));
  bool prev_ok = project(trajectory(0.0), prev_poly);
  for (size_t pi = 0; pi < num_polys; ++pi)
    for (int y = 0; y < params.height; ++y)
      prev_spans[pi][y] = prev_ok ? spanOnRow(prev_poly[pi], y) : RowSpan();

  // Occluded segment projected per step (for dropping its events).
  auto occluded = [&](const Pose& pose, double t, const Eigen::Vector2d& px) {
    if (params.occluded_segment < 0 || t < params.occlusion_start_s || t >= params.occlusion_end_s)
      return false;
    double best = std::numeric_limits<double>::max();
    int best_i = -1;
    for (size_t i = 0; i < map.segments.size(); ++i)
    {
      const Eigen::Vector3d a = pose.toCamera(map.segments[i].p0_world), b = pose.toCamera(map.segments[i].p1_world);
      if (a.z() < 1e-3 || b.z() < 1e-3)
        continue;
      const double d = distanceToSegment(px, params.k.project(a), params.k.project(b));
      if (d < best)
      {
        best = d;
        best_i = static_cast<int>(i);
      }
    }
    return best_i == params.occluded_segment;
  };

  const double noise_rate = params.noise_rate_hz_per_px * params.width * params.height;
  double next_noise = noise_rate > 0 ? -std::log(1.0 - uni(rng)) / noise_rate : std::numeric_limits<double>::max();

  std::vector<std::pair<double, dvs_driver::Event>> batch;
  std::vector<std::vector<RowSpan>> cur_spans(num_polys, std::vector<RowSpan>(params.height));
  double next_gt = 0.0;
  for (int step = 1; step <= steps; ++step)
  {
    const double t0 = (step - 1) * params.time_step_s, t1 = step * params.time_step_s;
    while (next_gt <= t1 + 1e-12 && next_gt <= params.duration_s + 1e-12)
    {
      seq.ground_truth.push_back({next_gt, trajectory(next_gt)});
      next_gt = std::round(next_gt * 1000.0 + 1.0) / 1000.0;
    }
    const Pose pose = trajectory(t1);
    const bool ok = project(pose, cur_poly);
    batch.clear();
    for (size_t pi = 0; pi < num_polys; ++pi)
      for (int y = 0; y < params.height; ++y)
      {
        const RowSpan s1 = ok ? spanOnRow(cur_poly[pi], y) : RowSpan();
        cur_spans[pi][y] = s1;
        const RowSpan& s0 = prev_spans[pi][y];
        int f0, l0, f1, l1;
        pixelRange(s0, params.width, f0, l0);
        pixelRange(s1, params.width, f1, l1);
        if (f0 == f1 && l0 == l1)
          continue;
        const int lo = std::min(l0 >= f0 ? f0 : f1, l1 >= f1 ? f1 : f0);
        const int hi = std::max(l0 >= f0 ? l0 : l1, l1 >= f1 ? l1 : l0);
        for (int x = lo; x <= hi; ++x)
        {
          const bool in0 = x >= f0 && x <= l0, in1 = x >= f1 && x <= l1;
          if (in0 == in1)
            continue;
          // Crossing time: interpolate the boundary that passed this pixel.
          double frac = 0.5;
          if (!s0.empty() && !s1.empty())
          {
            const bool left_side = std::abs(x - s0.left) + std::abs(x - s1.left) <
                                   std::abs(x - s0.right) + std::abs(x - s1.right);
            const double b0 = left_side ? s0.left : s0.right, b1 = left_side ? s1.left : s1.right;
            if (std::abs(b1 - b0) > 1e-12)
              frac = std::max(0.0, std::min(1.0, (x - b0) / (b1 - b0)));
          }
          const double t = t0 + frac * (t1 - t0);
          if (occluded(pose, t, Eigen::Vector2d(x, y)))
            continue;
          dvs_driver::Event e;
          e.x = static_cast<uint16_t>(x);
          e.y = static_cast<uint16_t>(y);
          e.polarity = !in1;  // leaving the dark polygon = brighter = ON
          for (int k = 0; k < params.events_per_crossing; ++k)
          {
            const double spread = params.events_per_crossing > 1
                                      ? (static_cast<double>(k) / (params.events_per_crossing - 1) - 0.5) * 0.5
                                      : 0.0;
            batch.emplace_back(std::max(t0, std::min(t1, t + spread * (t1 - t0))), e);
          }
        }
      }
    std::swap(prev_spans, cur_spans);
    while (next_noise <= t1)
    {
      dvs_driver::Event e;
      e.x = static_cast<uint16_t>(std::min<int>(params.width - 1, static_cast<int>(uni(rng) * params.width)));
      e.y = static_cast<uint16_t>(std::min<int>(params.height - 1, static_cast<int>(uni(rng) * params.height)));
      e.polarity = uni(rng) < 0.5;
      batch.emplace_back(next_noise, e);
      next_noise += -std::log(1.0 - uni(rng)) / noise_rate;
    }
    std::sort(batch.begin(), batch.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& [t, e] : batch)
    {
      e.t_ns = static_cast<int64_t>(std::llround(t * 1e9));
      seq.events.push_back(e);
    }
  }
  return seq;
}


}  // namespace dvs_line_tracker
