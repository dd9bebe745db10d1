#pragma once
// Focus assistant (thesis ch. 2.2.2): a sharpness score of the accumulated focus pattern that
// rises as the focus improves.
#include <opencv2/core.hpp>

namespace dvs_calibration
{
/// Sharpness of a per-pixel event-count image (CV_32S or CV_32F): the counts are normalised by
/// their 99th percentile (clipped at 1), so the score does not depend on the event rate; the
/// score is the mean squared Sobel gradient of the normalised image divided by its mean
/// (gradient energy per lit pixel), x 100. Blurring the pattern spreads the light over more
/// pixels with smaller steps between them and lowers the score. 0 for an empty image.
double focusScore(const cv::Mat& counts);
}  // namespace dvs_calibration
