#include <dvs_line_tracker/point_grid.h>

#include <limits>
#include <stdexcept>

namespace dvs_line_tracker
{
PointGrid::PointGrid(double cell_px) : base_cell_(cell_px), cell_(cell_px), half_diagonal_(cell_px * std::sqrt(0.5))
{
  if (!(cell_px > 0))
    throw std::invalid_argument("PointGrid: the cell size must be positive");
}

int PointGrid::cellOf(double v, double origin, int count) const
{
  // Clamped as a double first: a query may reach far beyond the points (a side projected from
  // near the camera plane).
  const double c = std::floor((v - origin) / cell_);
  return static_cast<int>(std::clamp(std::isnan(c) ? 0.0 : c, 0.0, static_cast<double>(count - 1)));
}

void PointGrid::reset(const std::vector<Eigen::Vector2d>& points)
{
  sorted_.clear();
  cols_ = rows_ = 0;
  // Finite points only (a non-finite one is near nothing).
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  for (const auto& p : points)
    if (p.allFinite())
    {
      xmin = std::min(xmin, p.x());
      ymin = std::min(ymin, p.y());
      xmax = std::max(xmax, p.x());
      ymax = std::max(ymax, p.y());
    }
  if (!(xmin <= xmax))
    return;
  x0_ = xmin;
  y0_ = ymin;
  // Ideal (undistorted) positions stay within a few sensor widths; the cap keeps stray points
  // from making the grid huge (the cells grow instead; queries stay supersets).
  constexpr double kMaxCells = 1 << 20;
  const double span_x = xmax - xmin, span_y = ymax - ymin;
  cell_ = base_cell_;
  if ((span_x / cell_ + 1) * (span_y / cell_ + 1) > kMaxCells)
    cell_ = std::sqrt((span_x + cell_) * (span_y + cell_) / kMaxCells) + cell_;
  half_diagonal_ = cell_ * std::sqrt(0.5);
  cols_ = static_cast<int>(span_x / cell_) + 1;
  rows_ = static_cast<int>(span_y / cell_) + 1;
  start_.assign(static_cast<size_t>(cols_) * rows_ + 1, 0);
  cell_of_.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i)
  {
    if (!points[i].allFinite())
    {
      cell_of_[i] = -1;
      continue;
    }
    cell_of_[i] = cellOf(points[i].y(), y0_, rows_) * cols_ + cellOf(points[i].x(), x0_, cols_);
    ++start_[cell_of_[i] + 1];
  }
  for (size_t c = 1; c < start_.size(); ++c)
    start_[c] += start_[c - 1];
  sorted_.resize(start_.back());
  std::vector<int> cursor(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < points.size(); ++i)
    if (cell_of_[i] >= 0)
      sorted_[cursor[cell_of_[i]]++] = points[i];
}

bool PointGrid::cellRange(double xmin, double ymin, double xmax, double ymax, int* c0, int* r0, int* c1, int* r1) const
{
  if (cols_ == 0 || !(xmin <= xmax) || !(ymin <= ymax))
    return false;
  if (xmax < x0_ || ymax < y0_ || xmin > x0_ + cols_ * cell_ || ymin > y0_ + rows_ * cell_)
    return false;
  *c0 = cellOf(xmin, x0_, cols_);
  *c1 = cellOf(xmax, x0_, cols_);
  *r0 = cellOf(ymin, y0_, rows_);
  *r1 = cellOf(ymax, y0_, rows_);
  return true;
}
}  // namespace dvs_line_tracker
