#pragma once
// Finding the calibration grid (white circles on black, thesis Fig. 2.1b) in one event window.
//
// Two ways to turn a window into a binary pattern image:
//  - counts (thesis ch. 2.2.3): pixels with more events than a threshold are white, then a
//    morphological closing fills holes and dents. Needs a still camera and a flickering
//    (dimmed) backlight or a blinking pattern.
//  - blinking pixels: a pixel is white when its events alternate ON/OFF often and in balance
//    (a blinking or flickering light), which rejects moving edges (one polarity per passing
//    edge) and static background. The alternative for cluttered or moving scenes.
// Then detectCircleGrid() orders the blobs with cv::findCirclesGrid (symmetric grid) and rejects
// partial or ambiguous detections.
#include <dvs_calibration/event_window.h>

#include <opencv2/core.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace dvs_calibration
{
/// Columns x rows of circles.
struct GridSize
{
  int cols = 7;
  int rows = 7;
};

/// Parse "7x7" (columns x rows, each 2..64). Throws std::invalid_argument naming the text.
GridSize parseGridSize(const std::string& text);

/// Counts -> binary image.
struct CountThresholdConfig
{
  /// Events per pixel and window for a white pixel; 0 = automatic (see below).
  int count_threshold = 0;
  /// Automatic threshold = max(min_count_threshold, fraction * 99th percentile of non-zero counts).
  double auto_threshold_fraction = 0.25;
  int min_count_threshold = 3;
  /// Side of the square structuring element of the closing, pixels (<= 1: no closing).
  int closing_size = 3;
};

/// Blinking-pixel detector (per-pixel ON/OFF timing).
struct BlinkDetectorConfig
{
  /// Minimum ON<->OFF alternations of a pixel in the window.
  int min_transitions = 2;
  /// Minimum min(ON, OFF) / max(ON, OFF) of a pixel.
  double min_polarity_balance = 0.3;
  int closing_size = 3;
};

/// Binary (0/255, CV_8U) pattern image from counts (CV_32S). `used_threshold` receives the threshold.
cv::Mat thresholdCounts(const cv::Mat& counts, const CountThresholdConfig& config, int* used_threshold = nullptr);
/// Binary (0/255, CV_8U) image of the blinking pixels of a window.
cv::Mat blinkingPixels(const EventWindow& window, const BlinkDetectorConfig& config);

struct GridDetectorConfig
{
  GridSize grid;
  /// Blobs (8-connected white regions) smaller than this are noise, pixels.
  int min_blob_area = 2;
  /// Blobs larger than this fraction of the image are not circles.
  double max_blob_area_fraction = 0.05;
  /// More blobs than this factor x the grid's circles: clutter or noise, rejected without
  /// running the grid finder (whose cost grows fast with the number of candidates).
  double max_candidates_factor = 2.0;
  /// Largest / smallest circle area allowed in one grid.
  double max_area_ratio = 5.0;
  /// RMS distance of the centres to the best plane-to-image homography, pixels (lens
  /// distortion bends the grid a little; motion and wrong orderings bend it a lot).
  double max_homography_rms_px = 1.5;
  /// A circle whose blob touches the image border is cut: the view is rejected (partial).
  bool reject_border_blobs = true;
  /// Centre = weighted centroid of the blob, weights = min(weight image, weight_clip x threshold).
  double weight_clip = 3.0;
};

struct GridDetection
{
  bool found = false;
  /// Why not found (empty when found).
  std::string reason;
  /// Circle centres in grid order: row-major, centres[r * cols + c] is object point (c, r) * spacing.
  /// The order is made right-handed (screen seen from the front: columns to the right of rows
  /// in the image turn clockwise), so calibrateCamera never sees a mirrored board.
  std::vector<cv::Point2f> centers;
  /// Blob centres found in the image (all candidates).
  std::vector<cv::Point2f> blobs;
  double homography_rms_px = 0;
};

/// Find the grid. `binary`: CV_8U 0/255; `weights`: CV_32S or CV_32F (counts or transitions)
/// for sub-pixel centres (empty: plain centroids); `weight_threshold` is the value a pixel needs
/// to be white (for clipping the weights).
GridDetection detectCircleGrid(const cv::Mat& binary, const cv::Mat& weights, double weight_threshold,
                               const GridDetectorConfig& config);

enum class DetectorKind
{
  Counts,  ///< thresholded event counts + closing (thesis)
  Blink    ///< per-pixel ON/OFF alternation (blinking pattern, robust to single moving edges and background)
};
/// "counts" or "blink"; throws std::invalid_argument naming the accepted values.
DetectorKind parseDetectorKind(const std::string& name);
std::string toString(DetectorKind kind);

struct WindowDetection
{
  cv::Mat binary;     ///< CV_8U pattern image of the accepted (or first) attempt
  int threshold = 0;  ///< count threshold (Counts) or minimum alternations (Blink) used
  GridDetection detection;
};

/// Detect the grid in one window: the configured binarisation first; when that fails, again
/// without closing (circles merged by the closing at strong tilts) and, for counts, without
/// closing at a 1.5x stricter threshold (circles grown into each other). Every attempt passes the
/// same rejection tests. Centres are weighted by the event counts.
WindowDetection detectGridInWindow(const EventWindow& window, DetectorKind kind, const CountThresholdConfig& counts,
                                   const BlinkDetectorConfig& blink, const GridDetectorConfig& grid);

/// The object points of a grid: (c * spacing, r * spacing, 0), row-major.
std::vector<cv::Point3f> gridObjectPoints(const GridSize& grid, double spacing);
}  // namespace dvs_calibration
