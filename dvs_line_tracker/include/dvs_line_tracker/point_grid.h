#pragma once
// The points of one detection attempt (the Hough window, the validation evidence) bucketed in
// square cells, so that a pose hypothesis's checks visit the points near its projected sides
// (or inside its polygon's box) instead of every point: on a 640x480 sensor the evidence holds
// tens of thousands of points, and every hypothesis tested each of them against every side.
// Queries visit a superset of the points in the region (whole cells), each once; the caller
// applies its exact test, so a check counts the same points as a scan of them all.
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dvs_line_tracker
{
class PointGrid
{
public:
  explicit PointGrid(double cell_px = 8.0);

  /// Bucket `points` (copied in cell order; the memory is reused).
  void reset(const std::vector<Eigen::Vector2d>& points);
  size_t size() const { return sorted_.size(); }

  /// Calls fn(p) for every point of the cells that may hold a point within `radius` of the
  /// segment a-b (its distance to the segment, ends included); every point within that distance
  /// is visited, once.
  template <class F>
  void forEachNearSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double radius, F&& fn) const
  {
    if (sorted_.empty() || !(radius >= 0) || !a.allFinite() || !b.allFinite())
      return;
    int c0, c1, r0, r1;
    if (!cellRange(std::min(a.x(), b.x()) - radius, std::min(a.y(), b.y()) - radius, std::max(a.x(), b.x()) + radius,
                   std::max(a.y(), b.y()) + radius, &c0, &r0, &c1, &r1))
      return;
    const Eigen::Vector2d d = b - a;
    const double len2 = d.squaredNorm();
    // A cell can hold such a point when its centre lies within radius + half its diagonal.
    const double reach = radius + half_diagonal_;
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c)
      {
        const Eigen::Vector2d centre(x0_ + (c + 0.5) * cell_, y0_ + (r + 0.5) * cell_);
        const double t = len2 > 0 ? std::clamp((centre - a).dot(d) / len2, 0.0, 1.0) : 0.0;
        if ((centre - (a + t * d)).squaredNorm() > reach * reach)
          continue;
        visitCell(r * cols_ + c, fn);
      }
  }

  /// Calls fn(p) for every point of the cells that overlap the box [lo, hi] (each point in the
  /// box is visited, once).
  template <class F>
  void forEachInBox(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, F&& fn) const
  {
    int c0, c1, r0, r1;
    if (sorted_.empty() || !cellRange(lo.x(), lo.y(), hi.x(), hi.y(), &c0, &r0, &c1, &r1))
      return;
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c)
        visitCell(r * cols_ + c, fn);
  }

private:
  template <class F>
  void visitCell(int cell, F& fn) const
  {
    for (int i = start_[cell]; i < start_[cell + 1]; ++i)
      fn(sorted_[i]);
  }
  /// The cells overlapping [xmin, xmax] x [ymin, ymax] (false: none).
  bool cellRange(double xmin, double ymin, double xmax, double ymax, int* c0, int* r0, int* c1, int* r1) const;
  int cellOf(double v, double origin, int count) const;

  double base_cell_, cell_, half_diagonal_;
  double x0_ = 0, y0_ = 0;  ///< the grid's corner (the points' minimum)
  int cols_ = 0, rows_ = 0;
  std::vector<int> start_;                 ///< per cell, its first point in sorted_ (cells + 1)
  std::vector<Eigen::Vector2d> sorted_;    ///< the points by cell
  std::vector<int> cell_of_;               ///< scratch
};
}  // namespace dvs_line_tracker
