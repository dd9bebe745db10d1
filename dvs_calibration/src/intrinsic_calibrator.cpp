#include <dvs_calibration/intrinsic_calibrator.h>

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace dvs_calibration
{
void validate(const CalibratorConfig& c)
{
  if (!(c.spacing_m > 0) || !std::isfinite(c.spacing_m))
    throw std::invalid_argument("spacing must be a positive distance in metres (got " + std::to_string(c.spacing_m) + ")");
  if (c.grid.cols < 2 || c.grid.rows < 2)
    throw std::invalid_argument("grid must have at least 2 columns and 2 rows");
  if (c.min_views < 3)
    throw std::invalid_argument("min_views must be at least 3 (got " + std::to_string(c.min_views) + ")");
  if (!(c.outlier_factor > 1))
    throw std::invalid_argument("outlier_factor must be > 1 (got " + std::to_string(c.outlier_factor) + ")");
  if (!(c.outlier_min_rms_px > 0))
    throw std::invalid_argument("outlier_min_rms_px must be > 0");
  if (c.max_outlier_rounds < 0)
    throw std::invalid_argument("max_outlier_rounds must be >= 0");
}

namespace
{
struct RunResult
{
  double rms = 0;
  cv::Mat K, D;
  std::vector<double> per_view;
  std::vector<cv::Vec3d> rvecs, tvecs;
};

RunResult runOnce(const std::vector<std::vector<cv::Point2f>>& views, const std::vector<size_t>& use, int width,
                  int height, const CalibratorConfig& config)
{
  const std::vector<cv::Point3f> object = gridObjectPoints(config.grid, config.spacing_m);
  std::vector<std::vector<cv::Point3f>> obj;
  std::vector<std::vector<cv::Point2f>> img;
  for (size_t i : use)
  {
    obj.push_back(object);
    img.push_back(views[i]);
  }
  int flags = 0;
  if (!config.estimate_k3)
    flags |= cv::CALIB_FIX_K3;
  if (!config.estimate_tangential)
    flags |= cv::CALIB_ZERO_TANGENT_DIST;
  RunResult r;
  r.K = cv::Mat::eye(3, 3, CV_64F);
  r.D = cv::Mat::zeros(1, 5, CV_64F);
  std::vector<cv::Mat> rv, tv;
  cv::Mat std_in, std_ex, per_view;
  const cv::TermCriteria term(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-12);
  r.rms = cv::calibrateCamera(obj, img, cv::Size(width, height), r.K, r.D, rv, tv, std_in, std_ex, per_view, flags, term);
  for (int i = 0; i < per_view.rows; ++i)
    r.per_view.push_back(per_view.at<double>(i));
  for (size_t i = 0; i < rv.size(); ++i)
  {
    r.rvecs.emplace_back(rv[i].at<double>(0), rv[i].at<double>(1), rv[i].at<double>(2));
    r.tvecs.emplace_back(tv[i].at<double>(0), tv[i].at<double>(1), tv[i].at<double>(2));
  }
  return r;
}
}  // namespace

CalibrationResult calibrateIntrinsics(const std::vector<std::vector<cv::Point2f>>& views, int width, int height,
                                      const CalibratorConfig& config)
{
  validate(config);
  const size_t n_points = static_cast<size_t>(config.grid.cols * config.grid.rows);
  for (size_t i = 0; i < views.size(); ++i)
    if (views[i].size() != n_points)
      throw CalibrationError("view " + std::to_string(i) + " has " + std::to_string(views[i].size()) +
                             " points, the grid has " + std::to_string(n_points));
  if (views.size() < config.min_views)
    throw CalibrationError("need at least " + std::to_string(config.min_views) + " views to calibrate, have " +
                           std::to_string(views.size()));

  CalibrationResult result;
  std::vector<size_t> use(views.size());
  for (size_t i = 0; i < use.size(); ++i)
    use[i] = i;

  RunResult run;
  try
  {
    run = runOnce(views, use, width, height, config);
    for (int round = 0; round < config.max_outlier_rounds; ++round)
    {
      std::vector<double> sorted = run.per_view;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
      const double median = sorted[sorted.size() / 2];
      const double limit = std::max(config.outlier_factor * median, config.outlier_min_rms_px);
      std::vector<size_t> keep;
      for (size_t i = 0; i < use.size(); ++i)
      {
        if (run.per_view[i] > limit)
          result.dropped_views.push_back(use[i]);
        else
          keep.push_back(use[i]);
      }
      if (keep.size() == use.size())
        break;
      if (keep.size() < config.min_views)
        throw CalibrationError("only " + std::to_string(keep.size()) + " views left after dropping outliers, need " +
                               std::to_string(config.min_views));
      use = keep;
      run = runOnce(views, use, width, height, config);
    }
  }
  catch (const cv::Exception& e)
  {
    throw CalibrationError(std::string("calibrateCamera failed: ") + e.what());
  }

  CameraIntrinsics k;
  k.width = width;
  k.height = height;
  k.fx = run.K.at<double>(0, 0);
  k.fy = run.K.at<double>(1, 1);
  k.cx = run.K.at<double>(0, 2);
  k.cy = run.K.at<double>(1, 2);
  k.k1 = run.D.at<double>(0);
  k.k2 = run.D.at<double>(1);
  k.p1 = run.D.at<double>(2);
  k.p2 = run.D.at<double>(3);
  k.k3 = run.D.at<double>(4);
  try
  {
    result.camera = CameraModel(k);
  }
  catch (const CameraModelError& e)
  {
    throw CalibrationError(std::string("calibration gave an invalid camera: ") + e.what());
  }
  result.rms_px = run.rms;
  result.per_view_rms_px = run.per_view;
  result.used_views = use;
  result.rvecs = run.rvecs;
  result.tvecs = run.tvecs;
  std::sort(result.dropped_views.begin(), result.dropped_views.end());
  return result;
}
}  // namespace dvs_calibration
