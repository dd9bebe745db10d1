#pragma once
// Intrinsic calibration from circle-grid views (cv::calibrateCamera, plumb_bob distortion),
// with per-view RMS reprojection errors and dropping of outlier views.
#include <dvs_calibration/camera_model.h>
#include <dvs_calibration/grid_detector.h>

#include <opencv2/core.hpp>

#include <stdexcept>
#include <vector>

namespace dvs_calibration
{
/// Thrown when there are too few views or the optimisation fails.
class CalibrationError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

struct CalibratorConfig
{
  GridSize grid;
  /// Centre-to-centre distance of neighbouring circles, metres (> 0).
  double spacing_m = 0.02;
  /// Estimate k3 too (a DVS128 lens rarely needs it; the ROS calibrator also fixes it by default).
  bool estimate_k3 = false;
  /// Estimate p1, p2 (tangential distortion).
  bool estimate_tangential = true;
  /// Fewer views than this: CalibrationError.
  size_t min_views = 5;
  /// A view is dropped when its RMS exceeds max(outlier_factor x median view RMS, outlier_min_rms_px).
  double outlier_factor = 3.0;
  double outlier_min_rms_px = 0.5;
  /// Rounds of drop-and-recalibrate.
  int max_outlier_rounds = 5;
};

/// Throws std::invalid_argument naming the bad field.
void validate(const CalibratorConfig& config);

struct CalibrationResult
{
  CameraModel camera;
  /// RMS reprojection error over all points of the used views, pixels.
  double rms_px = 0;
  /// Per used view (same order as used_views), pixels.
  std::vector<double> per_view_rms_px;
  /// Indices (into the input) of the views used and of those dropped as outliers.
  std::vector<size_t> used_views;
  std::vector<size_t> dropped_views;
  /// Poses of the grid in the camera (rvec, tvec), per used view.
  std::vector<cv::Vec3d> rvecs, tvecs;
};

/// Calibrate a width x height camera from views (each grid.cols * grid.rows centres in grid order).
CalibrationResult calibrateIntrinsics(const std::vector<std::vector<cv::Point2f>>& views, int width, int height,
                                      const CalibratorConfig& config);
}  // namespace dvs_calibration
