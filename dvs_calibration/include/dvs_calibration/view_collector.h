#pragma once
// The views (grid detections) kept for calibration, and when a new one is worth keeping.
#include <dvs_calibration/grid_detector.h>

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace dvs_calibration
{
struct View
{
  std::vector<cv::Point2f> centers;  ///< grid order (see GridDetection)
  int64_t t_ns = 0;                  ///< end of the window it was seen in
};

/// How far apart two detections of the same grid are, pixels, independent of which corner the
/// detector started at: the mean distance between the four outer corners, minimised over the
/// corner correspondences a symmetric grid allows (rotations and the mirror).
double viewDistance(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b, const GridSize& grid);

/// Mean distance of each point of `a` to the nearest point of `b` (order-free), pixels.
double meanNearestDistance(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b);

struct ViewCollectorConfig
{
  /// A new view is kept automatically when its viewDistance to every kept view is at least this, pixels.
  double min_view_difference_px = 8.0;
  /// At most this many views are kept (later ones are refused).
  size_t max_views = 200;
};

class ViewCollector
{
public:
  ViewCollector(const GridSize& grid, const ViewCollectorConfig& config) : grid_(grid), config_(config) {}

  /// Distance to the nearest kept view (infinity when none is kept).
  double distanceToNearest(const std::vector<cv::Point2f>& centers) const;
  /// True when the view differs enough from all kept ones and there is room.
  bool isNovel(const std::vector<cv::Point2f>& centers) const;
  /// Keep a view (no novelty check). Returns false when full.
  bool add(const View& view);
  void clear() { views_.clear(); }

  const std::vector<View>& views() const { return views_; }
  size_t size() const { return views_.size(); }
  const GridSize& grid() const { return grid_; }

private:
  GridSize grid_;
  ViewCollectorConfig config_;
  std::vector<View> views_;
};
}  // namespace dvs_calibration
