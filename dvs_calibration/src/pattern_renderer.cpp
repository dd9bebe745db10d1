#include <dvs_calibration/pattern_renderer.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dvs_calibration
{
cv::Mat renderFocusPattern(int width, int height, double scale_step, int border_px)
{
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("focus pattern size must be positive");
  if (!(scale_step > 0 && scale_step < 1))
    throw std::invalid_argument("focus pattern scale_step must be in (0, 1)");
  if (border_px < 0 || 2 * border_px >= std::min(width, height))
    throw std::invalid_argument("focus pattern border_px must be >= 0 and leave room for the pattern");
  cv::Mat img = cv::Mat::zeros(height, width, CV_8U);
  const double cx = 0.5 * width, cy = 0.5 * height;
  double half = 0.5 * std::min(width, height) - border_px;
  bool white = true;
  // Each band is the ring between squares of half-size `half` and `half * scale_step`; filling
  // squares from the outside in, alternately white and black, draws the rings.
  while (half >= 0.5)
  {
    const cv::Point tl(static_cast<int>(std::lround(cx - half)), static_cast<int>(std::lround(cy - half)));
    const cv::Point br(static_cast<int>(std::lround(cx + half)) - 1, static_cast<int>(std::lround(cy + half)) - 1);
    cv::rectangle(img, tl, br, cv::Scalar(white ? 255 : 0), cv::FILLED);
    white = !white;
    const double next = half * scale_step;
    if (half - next < 1.0)  // bands thinner than a screen pixel cannot be drawn
      break;
    half = next;
  }
  return img;
}

void validate(const CircleGridPattern& p, int width, int height)
{
  if (p.grid.cols < 2 || p.grid.rows < 2)
    throw std::invalid_argument("grid must have at least 2 columns and 2 rows");
  if (!(p.radius_fraction > 0 && p.radius_fraction < 0.5))
    throw std::invalid_argument("radius_fraction must be in (0, 0.5)");
  if (p.border_px < 0)
    throw std::invalid_argument("border must be >= 0 pixels");
  if (p.spacing_px < 0)
    throw std::invalid_argument("spacing must be >= 0 pixels (0 = largest that fits)");
  const double s = circleGridSpacingPx(width, height, p);
  const double r = p.radius_fraction * s;
  if (s < 4 || (p.grid.cols - 1) * s + 2 * r + 2 * p.border_px > width + 1e-9 ||
      (p.grid.rows - 1) * s + 2 * r + 2 * p.border_px > height + 1e-9)
    throw std::invalid_argument("a " + std::to_string(p.grid.cols) + "x" + std::to_string(p.grid.rows) +
                                " grid with these spacing/border does not fit in " + std::to_string(width) + "x" +
                                std::to_string(height) + " pixels");
}

double circleGridSpacingPx(int width, int height, const CircleGridPattern& p)
{
  if (p.spacing_px > 0)
    return p.spacing_px;
  const double sx = (width - 2.0 * p.border_px) / (p.grid.cols - 1 + 2 * p.radius_fraction);
  const double sy = (height - 2.0 * p.border_px) / (p.grid.rows - 1 + 2 * p.radius_fraction);
  return std::floor(std::min(sx, sy));
}

std::vector<cv::Point2d> circleGridCentersPx(int width, int height, const CircleGridPattern& p)
{
  const double s = circleGridSpacingPx(width, height, p);
  // Pixel centres at integer coordinates: the image centre is ((w-1)/2, (h-1)/2).
  const double x0 = 0.5 * (width - 1) - 0.5 * (p.grid.cols - 1) * s;
  const double y0 = 0.5 * (height - 1) - 0.5 * (p.grid.rows - 1) * s;
  std::vector<cv::Point2d> c;
  for (int r = 0; r < p.grid.rows; ++r)
    for (int k = 0; k < p.grid.cols; ++k)
      c.emplace_back(x0 + k * s, y0 + r * s);
  return c;
}

cv::Mat renderCircleGrid(int width, int height, const CircleGridPattern& p)
{
  validate(p, width, height);
  cv::Mat img = cv::Mat::zeros(height, width, CV_8U);
  const double r = p.radius_fraction * circleGridSpacingPx(width, height, p);
  constexpr int kShift = 4;  // sub-pixel centres and radius
  constexpr double kScale = 1 << kShift;
  for (const cv::Point2d& c : circleGridCentersPx(width, height, p))
    cv::circle(img, cv::Point(static_cast<int>(std::lround(c.x * kScale)), static_cast<int>(std::lround(c.y * kScale))),
               static_cast<int>(std::lround(r * kScale)), cv::Scalar(255), cv::FILLED, cv::LINE_AA, kShift);
  return img;
}

double screenPixelPitchMm(double screen_width_mm, int screen_width_px, double dpi)
{
  if (screen_width_mm > 0 && screen_width_px > 0)
    return screen_width_mm / screen_width_px;
  if (dpi > 0)
    return 25.4 / dpi;
  return 0.0;
}
}  // namespace dvs_calibration
