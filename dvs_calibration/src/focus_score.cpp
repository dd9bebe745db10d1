#include <dvs_calibration/focus_score.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <vector>

namespace dvs_calibration
{
double focusScore(const cv::Mat& counts)
{
  CV_Assert(counts.type() == CV_32S || counts.type() == CV_32F);
  cv::Mat f;
  counts.convertTo(f, CV_32F);
  std::vector<float> nz;
  nz.reserve(f.total());
  for (int r = 0; r < f.rows; ++r)
  {
    const float* p = f.ptr<float>(r);
    for (int c = 0; c < f.cols; ++c)
      if (p[c] > 0)
        nz.push_back(p[c]);
  }
  if (nz.empty())
    return 0.0;
  const size_t k = std::min(nz.size() - 1, static_cast<size_t>(0.99 * static_cast<double>(nz.size())));
  std::nth_element(nz.begin(), nz.begin() + static_cast<long>(k), nz.end());
  const float p99 = nz[k];
  if (p99 <= 0)
    return 0.0;
  cv::Mat n = cv::min(f / p99, 1.0f);
  const double mean = cv::mean(n)[0];
  if (mean <= 0)
    return 0.0;
  cv::Mat gx, gy;
  cv::Sobel(n, gx, CV_32F, 1, 0, 3, 1.0 / 8.0, 0, cv::BORDER_REPLICATE);
  cv::Sobel(n, gy, CV_32F, 0, 1, 3, 1.0 / 8.0, 0, cv::BORDER_REPLICATE);
  const double energy = cv::mean(gx.mul(gx) + gy.mul(gy))[0];
  return 100.0 * energy / mean;
}
}  // namespace dvs_calibration
