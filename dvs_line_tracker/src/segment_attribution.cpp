#include <dvs_line_tracker/segment_attribution.h>

namespace dvs_line_tracker
{
double clippedLength(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double x0, double y0, double x1, double y1,
                     Eigen::Vector2d* clipped_a, Eigen::Vector2d* clipped_b)
{
  const Eigen::Vector2d d = b - a;
  double t0 = 0, t1 = 1;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() - x0, x1 - a.x(), a.y() - y0, y1 - a.y()};
  for (int i = 0; i < 4; ++i)
  {
    if (std::abs(p[i]) < 1e-15)
    {
      if (q[i] < 0)
        return 0;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
    if (t0 > t1)
      return 0;
  }
  if (clipped_a)
    *clipped_a = a + t0 * d;
  if (clipped_b)
    *clipped_b = a + t1 * d;
  return (t1 - t0) * d.norm();
}
}  // namespace dvs_line_tracker
