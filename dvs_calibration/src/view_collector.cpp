#include <dvs_calibration/view_collector.h>

#include <array>
#include <limits>

namespace dvs_calibration
{
double viewDistance(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b, const GridSize& grid)
{
  const size_t n = static_cast<size_t>(grid.cols * grid.rows);
  if (a.size() != n || b.size() != n)
    return std::numeric_limits<double>::infinity();
  const auto corners = [&](const std::vector<cv::Point2f>& p) {
    return std::array<cv::Point2f, 4>{p[0], p[static_cast<size_t>(grid.cols - 1)], p[n - 1],
                                      p[static_cast<size_t>((grid.rows - 1) * grid.cols)]};
  };
  const std::array<cv::Point2f, 4> ca = corners(a), cb = corners(b);
  double best = std::numeric_limits<double>::infinity();
  for (int mirror = 0; mirror < 2; ++mirror)
    for (int shift = 0; shift < 4; ++shift)
    {
      double d = 0;
      for (int i = 0; i < 4; ++i)
      {
        const int j = mirror ? (shift - i + 8) % 4 : (shift + i) % 4;
        d += cv::norm(ca[static_cast<size_t>(i)] - cb[static_cast<size_t>(j)]);
      }
      best = std::min(best, d / 4.0);
    }
  return best;
}

double meanNearestDistance(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b)
{
  if (a.empty() || b.empty())
    return std::numeric_limits<double>::infinity();
  double sum = 0;
  for (const cv::Point2f& p : a)
  {
    double best = std::numeric_limits<double>::infinity();
    for (const cv::Point2f& q : b)
      best = std::min(best, static_cast<double>(cv::norm(p - q)));
    sum += best;
  }
  return sum / static_cast<double>(a.size());
}

double ViewCollector::distanceToNearest(const std::vector<cv::Point2f>& centers) const
{
  double best = std::numeric_limits<double>::infinity();
  for (const View& v : views_)
    best = std::min(best, viewDistance(centers, v.centers, grid_));
  return best;
}

bool ViewCollector::isNovel(const std::vector<cv::Point2f>& centers) const
{
  return views_.size() < config_.max_views && distanceToNearest(centers) >= config_.min_view_difference_px;
}

bool ViewCollector::add(const View& view)
{
  if (views_.size() >= config_.max_views)
    return false;
  views_.push_back(view);
  return true;
}
}  // namespace dvs_calibration
