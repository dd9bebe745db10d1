// Screen patterns (drawing), the focus score, and the undistorted event image.
#include "emulated_screen.h"

#include <dvs_calibration/event_image.h>
#include <dvs_calibration/event_window.h>
#include <dvs_calibration/focus_score.h>
#include <dvs_calibration/grid_detector.h>
#include <dvs_calibration/pattern_renderer.h>
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdlib>

#include <cmath>
#include <random>

using namespace dvs_calibration;

TEST(Pattern, CircleGridHasTheCirclesWhereItSays)
{
  CircleGridPattern p;
  p.border_px = 50;
  const int w = 1280, h = 800;
  const cv::Mat img = renderCircleGrid(w, h, p);
  ASSERT_EQ(img.type(), CV_8U);
  ASSERT_EQ(img.size(), cv::Size(w, h));
  const double s = circleGridSpacingPx(w, h, p);
  EXPECT_EQ(s, std::floor((800 - 100) / (6 + 0.6)));  // limited by the height
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(img > 127, labels, stats, centroids);
  ASSERT_EQ(n, 50);  // background + 49 circles
  const auto centres = circleGridCentersPx(w, h, p);
  ASSERT_EQ(centres.size(), 49u);
  // Row-major order, spacing s, centred.
  EXPECT_NEAR(centres[1].x - centres[0].x, s, 1e-9);
  EXPECT_NEAR(centres[7].y - centres[0].y, s, 1e-9);
  EXPECT_NEAR(0.5 * (centres[0].x + centres[48].x), 0.5 * (w - 1), 1e-9);
  for (int i = 1; i < n; ++i)
  {
    const cv::Point2d c(centroids.at<double>(i, 0), centroids.at<double>(i, 1));
    double best = 1e9;
    for (const auto& q : centres)
      best = std::min(best, cv::norm(c - q));
    EXPECT_LT(best, 0.05);
    EXPECT_NEAR(stats.at<int>(i, cv::CC_STAT_AREA), M_PI * std::pow(0.3 * s, 2), 0.05 * M_PI * std::pow(0.3 * s, 2));
  }
  // The margin is kept free (1 px for the anti-aliased edge).
  EXPECT_EQ(cv::countNonZero(img.rowRange(0, 49)), 0);
  EXPECT_EQ(cv::countNonZero(img.rowRange(h - 49, h)), 0);
}

TEST(Pattern, CircleGridIsFoundByTheDetectorOnTheScreenImage)
{
  CircleGridPattern p;
  p.border_px = 8;
  const cv::Mat img = renderCircleGrid(128, 128, p);
  GridDetectorConfig cfg;
  cv::Mat weights;
  img.convertTo(weights, CV_32S);
  const GridDetection det = detectCircleGrid(img > 127, weights, 255, cfg);
  ASSERT_TRUE(det.found) << det.reason;
  const auto truth = circleGridCentersPx(128, 128, p);
  for (size_t i = 0; i < truth.size(); ++i)
  {
    double best = 1e9;
    for (const auto& c : det.centers)
      best = std::min(best, cv::norm(cv::Point2d(c) - truth[i]));
    EXPECT_LT(best, 0.1);
  }
}

TEST(Pattern, RejectsGridsThatDoNotFit)
{
  CircleGridPattern p;
  p.spacing_px = 300;
  EXPECT_THROW(renderCircleGrid(1920, 1080, p), std::invalid_argument);
  p = CircleGridPattern();
  p.radius_fraction = 0.6;
  EXPECT_THROW(renderCircleGrid(1920, 1080, p), std::invalid_argument);
  p = CircleGridPattern();
  EXPECT_THROW(renderCircleGrid(100, 100, p), std::invalid_argument);  // border 40 leaves no room
  EXPECT_NO_THROW(renderCircleGrid(1920, 1080, CircleGridPattern()));
  EXPECT_NEAR(screenPixelPitchMm(527.0, 1920, 0), 527.0 / 1920, 1e-12);
  EXPECT_NEAR(screenPixelPitchMm(0, 0, 96), 25.4 / 96, 1e-12);
  EXPECT_EQ(screenPixelPitchMm(0, 0, 0), 0.0);
}

TEST(Pattern, FocusPatternIsConcentricLogScaledSquares)
{
  const double step = 0.8;
  const cv::Mat img = renderFocusPattern(1000, 1000, step, 0);
  ASSERT_EQ(img.type(), CV_8U);
  // Along the middle row from the left edge to the centre: alternating white/black bands whose
  // widths shrink by `step` (the half-sizes of the squares are 500 * step^k).
  const int row = 500;
  std::vector<int> widths;
  int run = 1;
  EXPECT_EQ(img.at<uint8_t>(row, 0), 255);  // outermost band white
  for (int x = 1; x < 500; ++x)
  {
    if (img.at<uint8_t>(row, x) == img.at<uint8_t>(row, x - 1))
      ++run;
    else
    {
      widths.push_back(run);
      run = 1;
    }
  }
  ASSERT_GE(widths.size(), 10u);
  for (size_t i = 0; i + 1 < 8; ++i)
    EXPECT_NEAR(static_cast<double>(widths[i + 1]) / widths[i], step, 0.05) << i;
  // Symmetric (a square pattern): transposed equals itself.
  cv::Mat t;
  cv::transpose(img, t);
  EXPECT_EQ(cv::norm(img, t, cv::NORM_L1), 0.0);
}

namespace
{
// The focus pattern seen by the emulated DVS through a lens whose defocus blurs it with a
// Gaussian of `sigma_px` sensor pixels: render at 4x, blur, average down, emit flicker events.
cv::Mat focusCounts(double sigma_px, std::mt19937& rng)
{
  const int up = 4;
  cv::Mat pattern;
  renderFocusPattern(128 * up, 128 * up, 0.8, 24 * up).convertTo(pattern, CV_32F, 1.0 / 255);
  if (sigma_px > 0)
    cv::GaussianBlur(pattern, pattern, cv::Size(0, 0), sigma_px * up);
  cv::Mat coverage;
  cv::resize(pattern, coverage, cv::Size(128, 128), 0, 0, cv::INTER_AREA);
  dvs_calibration::testing::EmulatedScreen screen;
  const auto ev = dvs_calibration::testing::emulateEvents(screen, coverage, 0, 150000000, rng);
  EventWindow win(128, 128);
  win.reset(0, 150000000);
  for (const auto& e : ev)
    win.add(e);
  return win.counts();
}
}  // namespace

TEST(FocusScore, PeaksAtTheSharpestFocus)
{
  // Lens positions -4..4, in focus at +1: blur sigma = 0.6 px per step away from focus.
  std::mt19937 rng(12);
  std::vector<double> scores;
  for (int pos = -4; pos <= 4; ++pos)
  {
    const double sigma = 0.6 * std::abs(pos - 1);
    scores.push_back(focusScore(focusCounts(sigma, rng)));
  }
  const size_t best = static_cast<size_t>(std::max_element(scores.begin(), scores.end()) - scores.begin());
  EXPECT_EQ(static_cast<int>(best) - 4, 1);
  // Rises towards the focus from both sides.
  for (size_t i = 0; i < best; ++i)
    EXPECT_LT(scores[i], scores[i + 1]) << "position " << static_cast<int>(i) - 4;
  for (size_t i = best; i + 1 < scores.size(); ++i)
    EXPECT_GT(scores[i], scores[i + 1]) << "position " << static_cast<int>(i) - 4;
}

TEST(FocusScore, DoesNotDependOnTheEventRate)
{
  std::mt19937 rng(13);
  const cv::Mat counts = focusCounts(0.5, rng);
  const double a = focusScore(counts);
  EXPECT_GT(a, 0);
  EXPECT_NEAR(focusScore(counts * 3), a, 1e-6 * a);
  EXPECT_EQ(focusScore(cv::Mat::zeros(128, 128, CV_32S)), 0.0);
}

TEST(EventImage, UndistortedCountsMoveEachPixelToItsIdealPosition)
{
  const CameraModel cam = CameraModel::dvs128();
  for (const cv::Point p : {cv::Point(5, 7), cv::Point(64, 64), cv::Point(120, 20), cv::Point(30, 100)})
  {
    cv::Mat counts = cv::Mat::zeros(128, 128, CV_32S);
    counts.at<int32_t>(p) = 10;
    const cv::Mat und = undistortCounts(counts, cam);
    const cv::Moments m = cv::moments(und);
    const Eigen::Vector2d ideal = cam.undistortPixel(Eigen::Vector2d(p.x, p.y));
    if (!cam.inImage(ideal, 1.0))
      continue;
    EXPECT_NEAR(m.m00, 10.0, 1e-4);                // mass kept
    EXPECT_NEAR(m.m10 / m.m00, ideal.x(), 1e-3);   // bilinear splat centred on the ideal pixel
    EXPECT_NEAR(m.m01 / m.m00, ideal.y(), 1e-3);
  }
  // Barrel distortion (k1 < 0): a corner pixel moves outwards when undistorted.
  const Eigen::Vector2d corner = cam.undistortPixel(Eigen::Vector2d(5, 7));
  EXPECT_LT(corner.x(), 5.0);
  EXPECT_LT(corner.y(), 7.0);
}

TEST(EventImage, PreviewShowsTheCountsAndTheScore)
{
  cv::Mat counts = cv::Mat::zeros(128, 128, CV_32S);
  counts(cv::Rect(40, 40, 20, 20)).setTo(7);
  const cv::Mat img = countsToImage(counts);
  EXPECT_EQ(img.at<uint8_t>(50, 50), 255);
  EXPECT_EQ(img.at<uint8_t>(10, 10), 0);
  const cv::Mat preview = renderPreview(counts, {}, 7, 12.5, 4);
  EXPECT_EQ(preview.size(), cv::Size(512, 512));
  EXPECT_EQ(preview.type(), CV_8UC3);
  const cv::Vec3b centre = preview.at<cv::Vec3b>(200, 200);
  EXPECT_EQ(centre, cv::Vec3b(255, 255, 255));
}

TEST(ShowPattern, SavesTheSamePatternAndRunsUnderXvfb)
{
  const std::string png = ::testing::TempDir() + "/show_pattern_grid.png";
  const std::string tool = DVS_SHOW_PATTERN_TOOL;
  ASSERT_EQ(std::system((tool + " --save " + png + " --resolution 1280x800 --border 30 > /dev/null").c_str()), 0);
  CircleGridPattern p;
  p.border_px = 30;
  const cv::Mat expected = renderCircleGrid(1280, 800, p);
  const cv::Mat saved = cv::imread(png, cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(saved.size(), expected.size());
  EXPECT_EQ(cv::norm(saved, expected, cv::NORM_INF), 0.0);
  // Bad arguments: exit status 2.
  EXPECT_NE(std::system((tool + " --pattern stars --save " + png + " 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system((tool + " --grid 7 --save " + png + " 2>/dev/null").c_str()), 0);
  // The window loop: a few blinking frames on a virtual X server.
  ASSERT_EQ(std::system(("xvfb-run -a -s '-screen 0 1024x768x24' " + tool +
                         " --frames 6 --blink-hz 10 --dpi 96 > /dev/null 2>&1").c_str()),
            0);
}
