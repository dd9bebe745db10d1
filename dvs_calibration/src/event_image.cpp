#include <dvs_calibration/event_image.h>

#include <dvs_driver/checked_write.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace dvs_calibration
{
cv::Mat countsToImage(const cv::Mat& counts)
{
  cv::Mat f;
  counts.convertTo(f, CV_32F);
  std::vector<float> nz;
  for (int r = 0; r < f.rows; ++r)
    for (int c = 0; c < f.cols; ++c)
      if (f.at<float>(r, c) > 0)
        nz.push_back(f.at<float>(r, c));
  cv::Mat out;
  if (nz.empty())
    return cv::Mat::zeros(f.size(), CV_8U);
  const size_t k = std::min(nz.size() - 1, static_cast<size_t>(0.99 * static_cast<double>(nz.size())));
  std::nth_element(nz.begin(), nz.begin() + static_cast<long>(k), nz.end());
  f.convertTo(out, CV_8U, 255.0 / std::max(1e-6f, nz[k]));
  return out;
}

cv::Mat undistortCounts(const cv::Mat& counts, const CameraModel& camera)
{
  CV_Assert(counts.rows == camera.height() && counts.cols == camera.width());
  cv::Mat f;
  counts.convertTo(f, CV_32F);
  cv::Mat out = cv::Mat::zeros(f.size(), CV_32F);
  for (int y = 0; y < f.rows; ++y)
    for (int x = 0; x < f.cols; ++x)
    {
      const float v = f.at<float>(y, x);
      if (v == 0)
        continue;
      const Eigen::Vector2f& p = camera.undistortedPixelLut(x, y);
      const int x0 = static_cast<int>(std::floor(p.x())), y0 = static_cast<int>(std::floor(p.y()));
      const float ax = p.x() - x0, ay = p.y() - y0;
      const float w[4] = {(1 - ax) * (1 - ay), ax * (1 - ay), (1 - ax) * ay, ax * ay};
      const int xs[4] = {x0, x0 + 1, x0, x0 + 1}, ys[4] = {y0, y0, y0 + 1, y0 + 1};
      for (int i = 0; i < 4; ++i)
        if (xs[i] >= 0 && ys[i] >= 0 && xs[i] < out.cols && ys[i] < out.rows)
          out.at<float>(ys[i], xs[i]) += w[i] * v;
    }
  return out;
}

cv::Mat countEvents(const dvs_driver::EventVector& events, int width, int height)
{
  cv::Mat counts = cv::Mat::zeros(height, width, CV_32S);
  for (const dvs_driver::Event& e : events)
    if (e.x < width && e.y < height)
      ++counts.at<int32_t>(e.y, e.x);
  return counts;
}

cv::Mat renderPreview(const cv::Mat& counts, const std::vector<cv::Point2f>& grid_centers, int grid_cols,
                      double focus_score, int upscale)
{
  upscale = std::max(1, upscale);
  cv::Mat grey = countsToImage(counts), big, bgr;
  cv::resize(grey, big, cv::Size(), upscale, upscale, cv::INTER_NEAREST);
  cv::cvtColor(big, bgr, cv::COLOR_GRAY2BGR);
  if (!grid_centers.empty() && grid_cols > 0)
  {
    std::vector<cv::Point2f> scaled;
    for (const cv::Point2f& p : grid_centers)
      scaled.emplace_back((p.x + 0.5f) * upscale - 0.5f, (p.y + 0.5f) * upscale - 0.5f);
    const int rows = static_cast<int>(grid_centers.size()) / grid_cols;
    cv::drawChessboardCorners(bgr, cv::Size(grid_cols, rows), scaled, true);
  }
  char text[64];
  std::snprintf(text, sizeof(text), "focus %.1f", focus_score);
  cv::putText(bgr, text, cv::Point(4, 16), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 255, 255), 1, cv::LINE_AA);
  return bgr;
}
void writeImageChecked(const std::string& path, const cv::Mat& image)
{
  const size_t dot = path.rfind('.');
  const std::string ext = dot == std::string::npos ? std::string() : path.substr(dot);
  std::vector<uchar> bytes;
  bool encoded = false;
  try
  {
    encoded = !ext.empty() && cv::imencode(ext, image, bytes);
  }
  catch (const cv::Exception&)
  {
    encoded = false;
  }
  if (!encoded)
    throw dvs_driver::WriteError(path, "cannot encode the image as '" + ext + "' (use .png or .jpg)");
  dvs_driver::writeFileChecked(path, std::string(bytes.begin(), bytes.end()));
}
}  // namespace dvs_calibration
