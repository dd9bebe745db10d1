#include <dvs_calibration/grid_detector.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace dvs_calibration
{
namespace
{
void closeInPlace(cv::Mat& binary, int size)
{
  if (size <= 1)
    return;
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size));
  // Default border value: the image border neither grows nor erodes blobs (a circle cut by the
  // border must keep touching it).
  cv::morphologyEx(binary, binary, cv::MORPH_CLOSE, kernel);
}

int percentileOfNonZero(const cv::Mat& counts, double q)
{
  std::vector<int32_t> v;
  v.reserve(static_cast<size_t>(counts.total()));
  for (int r = 0; r < counts.rows; ++r)
  {
    const int32_t* p = counts.ptr<int32_t>(r);
    for (int c = 0; c < counts.cols; ++c)
      if (p[c] > 0)
        v.push_back(p[c]);
  }
  if (v.empty())
    return 0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

double cross2(const cv::Point2f& a, const cv::Point2f& b) { return static_cast<double>(a.x) * b.y - static_cast<double>(a.y) * b.x; }
}  // namespace

GridSize parseGridSize(const std::string& text)
{
  const size_t x = text.find_first_of("xX");
  GridSize g;
  try
  {
    if (x == std::string::npos)
      throw std::invalid_argument("");
    size_t used = 0;
    g.cols = std::stoi(text.substr(0, x), &used);
    if (used != x)
      throw std::invalid_argument("");
    const std::string rows = text.substr(x + 1);
    g.rows = std::stoi(rows, &used);
    if (used != rows.size())
      throw std::invalid_argument("");
  }
  catch (const std::exception&)
  {
    throw std::invalid_argument("grid size '" + text + "' is not COLUMNSxROWS (e.g. 7x7)");
  }
  if (g.cols < 2 || g.rows < 2 || g.cols > 64 || g.rows > 64)
    throw std::invalid_argument("grid size '" + text + "': columns and rows must be 2..64");
  return g;
}

cv::Mat thresholdCounts(const cv::Mat& counts, const CountThresholdConfig& config, int* used_threshold)
{
  CV_Assert(counts.type() == CV_32S);
  int threshold = config.count_threshold;
  if (threshold <= 0)
  {
    const int p99 = percentileOfNonZero(counts, 0.99);
    threshold = std::max(config.min_count_threshold,
                         static_cast<int>(std::ceil(config.auto_threshold_fraction * static_cast<double>(p99))));
  }
  if (used_threshold)
    *used_threshold = threshold;
  cv::Mat binary = counts >= threshold;  // CV_8U 0/255
  closeInPlace(binary, config.closing_size);
  return binary;
}

cv::Mat blinkingPixels(const EventWindow& window, const BlinkDetectorConfig& config)
{
  cv::Mat binary = cv::Mat::zeros(window.height(), window.width(), CV_8U);
  for (int r = 0; r < window.height(); ++r)
  {
    const int32_t* on = window.onCounts().ptr<int32_t>(r);
    const int32_t* off = window.offCounts().ptr<int32_t>(r);
    const int32_t* tr = window.transitions().ptr<int32_t>(r);
    uint8_t* out = binary.ptr<uint8_t>(r);
    for (int c = 0; c < window.width(); ++c)
    {
      if (tr[c] < config.min_transitions)
        continue;
      const double lo = std::min(on[c], off[c]);
      const double hi = std::max(on[c], off[c]);
      if (hi > 0 && lo >= config.min_polarity_balance * hi)
        out[c] = 255;
    }
  }
  closeInPlace(binary, config.closing_size);
  return binary;
}

std::vector<cv::Point3f> gridObjectPoints(const GridSize& grid, double spacing)
{
  std::vector<cv::Point3f> pts;
  pts.reserve(static_cast<size_t>(grid.cols * grid.rows));
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c)
      pts.emplace_back(static_cast<float>(c * spacing), static_cast<float>(r * spacing), 0.f);
  return pts;
}

GridDetection detectCircleGrid(const cv::Mat& binary, const cv::Mat& weights, double weight_threshold,
                               const GridDetectorConfig& config)
{
  CV_Assert(binary.type() == CV_8U);
  GridDetection det;
  const int n_grid = config.grid.cols * config.grid.rows;

  // Blobs: 8-connected components with their (weighted) centroids.
  cv::Mat labels, stats, centroids;
  const int n_labels = cv::connectedComponentsWithStats(binary, labels, stats, centroids, 8, CV_32S);
  const double max_area = config.max_blob_area_fraction * static_cast<double>(binary.total());
  cv::Mat w;
  if (!weights.empty())
    weights.convertTo(w, CV_32F);
  const float clip = static_cast<float>(std::max(1.0, config.weight_clip * weight_threshold));

  std::vector<double> sum_w(static_cast<size_t>(n_labels), 0.0), sum_x(sum_w), sum_y(sum_w);
  for (int r = 0; r < labels.rows; ++r)
  {
    const int32_t* l = labels.ptr<int32_t>(r);
    const float* wr = w.empty() ? nullptr : w.ptr<float>(r);
    for (int c = 0; c < labels.cols; ++c)
    {
      if (l[c] == 0)
        continue;
      // Pixels added by the closing have no weight of their own: give them a small one.
      const double wi = wr ? std::max(0.1, static_cast<double>(std::min(wr[c], clip))) : 1.0;
      sum_w[static_cast<size_t>(l[c])] += wi;
      sum_x[static_cast<size_t>(l[c])] += wi * c;
      sum_y[static_cast<size_t>(l[c])] += wi * r;
    }
  }
  std::vector<int> blob_label;
  for (int i = 1; i < n_labels; ++i)
  {
    const int area = stats.at<int>(i, cv::CC_STAT_AREA);
    if (area < config.min_blob_area || area > max_area)
      continue;
    const auto k = static_cast<size_t>(i);
    det.blobs.emplace_back(static_cast<float>(sum_x[k] / sum_w[k]), static_cast<float>(sum_y[k] / sum_w[k]));
    blob_label.push_back(i);
  }
  if (static_cast<int>(det.blobs.size()) < n_grid)
  {
    det.reason = "only " + std::to_string(det.blobs.size()) + " blobs, need " + std::to_string(n_grid);
    return det;
  }
  if (static_cast<double>(det.blobs.size()) > config.max_candidates_factor * n_grid)
  {
    det.reason = "too many blobs (" + std::to_string(det.blobs.size()) + "): noise or clutter";
    return det;
  }

  std::vector<cv::Point2f> centers;
  bool ok = false;
  try
  {
    ok = cv::findCirclesGrid(det.blobs, cv::Size(config.grid.cols, config.grid.rows), centers,
                             cv::CALIB_CB_SYMMETRIC_GRID, cv::Ptr<cv::FeatureDetector>());
  }
  catch (const cv::Exception&)
  {
    ok = false;
  }
  if (!ok || static_cast<int>(centers.size()) != n_grid)
  {
    det.reason = "blobs do not form a " + std::to_string(config.grid.cols) + "x" + std::to_string(config.grid.rows) +
                 " grid";
    return det;
  }

  // Which blob is each centre (findCirclesGrid returns the candidate points themselves).
  std::vector<int> member(static_cast<size_t>(n_grid), -1);
  std::vector<bool> used(det.blobs.size(), false);
  for (int i = 0; i < n_grid; ++i)
  {
    double best = 1e9;
    for (size_t b = 0; b < det.blobs.size(); ++b)
    {
      const double d = cv::norm(det.blobs[b] - centers[static_cast<size_t>(i)]);
      if (d < best)
      {
        best = d;
        member[static_cast<size_t>(i)] = static_cast<int>(b);
      }
    }
    if (best > 1e-3 || used[static_cast<size_t>(member[static_cast<size_t>(i)])])
    {
      det.reason = "grid points do not match distinct blobs";
      return det;
    }
    used[static_cast<size_t>(member[static_cast<size_t>(i)])] = true;
  }

  // Partial: a circle cut by the image border.
  double min_area = 1e18, max_area_seen = 0;
  for (int i = 0; i < n_grid; ++i)
  {
    const int lab = blob_label[static_cast<size_t>(member[static_cast<size_t>(i)])];
    const int x = stats.at<int>(lab, cv::CC_STAT_LEFT), y = stats.at<int>(lab, cv::CC_STAT_TOP);
    const int bw = stats.at<int>(lab, cv::CC_STAT_WIDTH), bh = stats.at<int>(lab, cv::CC_STAT_HEIGHT);
    if (config.reject_border_blobs && (x <= 0 || y <= 0 || x + bw >= binary.cols || y + bh >= binary.rows))
    {
      det.reason = "partial: a circle touches the image border";
      return det;
    }
    const double a = stats.at<int>(lab, cv::CC_STAT_AREA);
    min_area = std::min(min_area, a);
    max_area_seen = std::max(max_area_seen, a);
  }
  if (max_area_seen > config.max_area_ratio * min_area)
  {
    det.reason = "circle sizes differ too much (merged or broken blobs)";
    return det;
  }

  // Right-handed order: (column step) x (row step) > 0 in image coordinates (y down).
  const cv::Point2f col_step = centers[static_cast<size_t>(config.grid.cols - 1)] - centers[0];
  const cv::Point2f row_step = centers[static_cast<size_t>((config.grid.rows - 1) * config.grid.cols)] - centers[0];
  if (cross2(col_step, row_step) < 0)
  {
    for (int r = 0; r < config.grid.rows; ++r)
      std::reverse(centers.begin() + r * config.grid.cols, centers.begin() + (r + 1) * config.grid.cols);
  }

  // Regularity: centres must fit a homography of the plane grid.
  std::vector<cv::Point2f> plane;
  for (int r = 0; r < config.grid.rows; ++r)
    for (int c = 0; c < config.grid.cols; ++c)
      plane.emplace_back(static_cast<float>(c), static_cast<float>(r));
  const cv::Mat H = cv::findHomography(plane, centers, 0);
  if (H.empty())
  {
    det.reason = "degenerate grid";
    return det;
  }
  std::vector<cv::Point2f> predicted;
  cv::perspectiveTransform(plane, predicted, H);
  double sq = 0;
  for (int i = 0; i < n_grid; ++i)
    sq += std::pow(cv::norm(predicted[static_cast<size_t>(i)] - centers[static_cast<size_t>(i)]), 2);
  det.homography_rms_px = std::sqrt(sq / n_grid);
  if (det.homography_rms_px > config.max_homography_rms_px)
  {
    det.reason = "grid not regular (homography RMS " + std::to_string(det.homography_rms_px) + " px)";
    return det;
  }

  // Ambiguity: another blob where the grid would continue (one ring outside), or between grid points.
  double spacing = 0;
  for (int r = 0; r < config.grid.rows; ++r)
    for (int c = 0; c + 1 < config.grid.cols; ++c)
      spacing += cv::norm(centers[static_cast<size_t>(r * config.grid.cols + c + 1)] -
                          centers[static_cast<size_t>(r * config.grid.cols + c)]);
  spacing /= config.grid.rows * (config.grid.cols - 1);
  std::vector<cv::Point2f> probe_plane;
  for (int r = -1; r <= config.grid.rows; ++r)
    for (int c = -1; c <= config.grid.cols; ++c)
    {
      const bool inside = r >= 0 && c >= 0 && r < config.grid.rows && c < config.grid.cols;
      if (!inside)
        probe_plane.emplace_back(static_cast<float>(c), static_cast<float>(r));
      // half-way points between grid points (a blob there is not part of a regular grid)
      if (r >= 0 && c >= 0 && r + 1 < config.grid.rows && c + 1 < config.grid.cols)
        probe_plane.emplace_back(c + 0.5f, r + 0.5f);
    }
  std::vector<cv::Point2f> probes;
  cv::perspectiveTransform(probe_plane, probes, H);
  for (size_t b = 0; b < det.blobs.size(); ++b)
  {
    if (used[b])
      continue;
    for (const cv::Point2f& p : probes)
      if (cv::norm(det.blobs[b] - p) < 0.4 * spacing)
      {
        det.reason = "ambiguous: another blob continues the grid or lies inside it";
        return det;
      }
  }

  det.centers = std::move(centers);
  det.found = true;
  return det;
}
}  // namespace dvs_calibration

namespace dvs_calibration
{
DetectorKind parseDetectorKind(const std::string& name)
{
  if (name == "counts")
    return DetectorKind::Counts;
  if (name == "blink")
    return DetectorKind::Blink;
  throw std::invalid_argument("detector '" + name + "' is unknown: use 'counts' or 'blink'");
}

std::string toString(DetectorKind kind) { return kind == DetectorKind::Counts ? "counts" : "blink"; }

WindowDetection detectGridInWindow(const EventWindow& window, DetectorKind kind, const CountThresholdConfig& counts_cfg,
                                   const BlinkDetectorConfig& blink_cfg, const GridDetectorConfig& grid_cfg)
{
  WindowDetection out;
  const cv::Mat counts = window.counts();
  // The automatic count threshold also clips the centre weights of the blink detector.
  CountThresholdConfig auto_cfg = counts_cfg;
  int base = 0;
  thresholdCounts(counts, auto_cfg, &base);
  const int closing0 = kind == DetectorKind::Counts ? counts_cfg.closing_size : blink_cfg.closing_size;
  // Attempts (closing size, threshold factor): as configured; without closing (circles merged by
  // the closing at strong tilts); for counts also 1.5x stricter (blooming circles touching).
  struct Attempt
  {
    int closing;
    double factor;
  };
  std::vector<Attempt> attempts = {{closing0, 1.0}};
  if (closing0 > 1)
    attempts.push_back({0, 1.0});
  if (kind == DetectorKind::Counts)
    attempts.push_back({0, 1.5});
  for (const Attempt& attempt : attempts)
    {
      const double factor = attempt.factor;
      cv::Mat binary;
      int threshold = 0;
      if (kind == DetectorKind::Counts)
      {
        CountThresholdConfig t = counts_cfg;
        t.closing_size = attempt.closing;
        t.count_threshold = static_cast<int>(std::ceil(base * factor));
        binary = thresholdCounts(counts, t, &threshold);
      }
      else
      {
        BlinkDetectorConfig b = blink_cfg;
        b.closing_size = attempt.closing;
        b.min_transitions = static_cast<int>(std::ceil(b.min_transitions * factor));
        binary = blinkingPixels(window, b);
        threshold = b.min_transitions;
      }
      GridDetection det = detectCircleGrid(binary, counts, base * factor, grid_cfg);
      if (out.binary.empty() || det.found)
      {
        out.binary = binary;
        out.threshold = threshold;
        out.detection = std::move(det);
      }
      if (out.detection.found)
        return out;
    }
  return out;
}
}  // namespace dvs_calibration
