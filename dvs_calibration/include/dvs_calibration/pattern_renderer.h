#pragma once
// The patterns shown on the screen (thesis Fig. 2.1): drawing only, no window, so the display
// program, the tests and the screen-in-the-loop work share them.
#include <dvs_calibration/grid_detector.h>

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace dvs_calibration
{
/// Focus pattern (Fig. 2.1a): concentric square outlines, alternately white and black, each
/// square `scale_step` (0 < step < 1) times the size of the one outside it (logarithmic
/// scaling: thick bands outside, thin ones near the centre), down to bands of about one screen
/// pixel. The outermost band is white and fills the image minus `border_px`. CV_8U, 0/255.
cv::Mat renderFocusPattern(int width, int height, double scale_step = 0.8, int border_px = 0);

struct CircleGridPattern
{
  GridSize grid;
  /// Centre-to-centre distance, screen pixels; 0 = the largest that fits inside the border.
  double spacing_px = 0;
  /// Circle radius as a fraction of the spacing (0 < f < 0.5).
  double radius_fraction = 0.3;
  /// Black margin kept free around the grid's outer circles, screen pixels.
  int border_px = 40;
};

/// Throws std::invalid_argument naming the field (grid, radius_fraction, border) or when the grid
/// does not fit in width x height.
void validate(const CircleGridPattern& pattern, int width, int height);
/// The spacing actually drawn, screen pixels.
double circleGridSpacingPx(int width, int height, const CircleGridPattern& pattern);
/// Circle centres in screen pixels, row-major (centre (c, r) at index r * cols + c), the grid
/// centred in the image.
std::vector<cv::Point2d> circleGridCentersPx(int width, int height, const CircleGridPattern& pattern);
/// Calibration pattern (Fig. 2.1b): white anti-aliased circles on black. CV_8U.
cv::Mat renderCircleGrid(int width, int height, const CircleGridPattern& pattern);

/// Physical size of one screen pixel, millimetres, from the screen's width in mm and pixels, or
/// from dots per inch (pass 0 for the one not known). Returns 0 when neither is given.
double screenPixelPitchMm(double screen_width_mm, int screen_width_px, double dpi);
}  // namespace dvs_calibration
