// Grid detection: found on emulated views with sub-pixel centres; partial and ambiguous grids,
// pure noise, moving edges and real recordings (../shared/data/real) give no detection.
#include "emulated_screen.h"

#include <dvs_calibration/calibration_session.h>
#include <dvs_calibration/grid_detector.h>
#include <dvs_driver/aedat_reader.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace dvs_calibration;
using dvs_calibration::testing::EmulatedScreen;
using dvs_calibration::testing::ScreenPose;

namespace
{
EventWindow windowOf(const dvs_driver::EventVector& ev, int w, int h, int64_t t0, int64_t t1)
{
  EventWindow win(w, h);
  win.reset(t0, t1);
  for (const auto& e : ev)
    if (e.t_ns >= t0 && e.t_ns < t1)
      win.add(e);
  return win;
}

GridDetection detectCounts(const EventWindow& win, const GridSize& grid = GridSize())
{
  GridDetectorConfig cfg;
  cfg.grid = grid;
  return detectGridInWindow(win, DetectorKind::Counts, CountThresholdConfig(), BlinkDetectorConfig(), cfg).detection;
}

double orientation(const std::vector<cv::Point2f>& c, const GridSize& g)
{
  const cv::Point2f a = c[static_cast<size_t>(g.cols - 1)] - c[0];
  const cv::Point2f b = c[static_cast<size_t>((g.rows - 1) * g.cols)] - c[0];
  return a.x * b.y - a.y * b.x;
}

// RMS distance from each detected centre to the nearest true centre.
double rmsToTruth(const std::vector<cv::Point2f>& det, const std::vector<cv::Point2f>& truth)
{
  double sq = 0;
  for (const auto& p : det)
  {
    double best = 1e9;
    for (const auto& q : truth)
      best = std::min(best, static_cast<double>(cv::norm(p - q)));
    sq += best * best;
  }
  return std::sqrt(sq / det.size());
}

size_t sessionDetections(const dvs_driver::EventStream& s, DetectorKind kind, size_t* windows)
{
  SessionConfig cfg;
  cfg.width = static_cast<int>(s.width);
  cfg.height = static_cast<int>(s.height);
  cfg.detector = kind;
  CalibrationSession session(cfg);
  session.addEvents(s.events);
  session.flush();
  *windows = session.windowsProcessed();
  return session.detections();
}
}  // namespace

TEST(GridDetection, ParsesGridSize)
{
  const GridSize g = parseGridSize("7x5");
  EXPECT_EQ(g.cols, 7);
  EXPECT_EQ(g.rows, 5);
  EXPECT_EQ(parseGridSize("4X11").rows, 11);
  for (const char* bad : {"7", "7x", "x7", "7x7x", "1x7", "7x0", "axb", "7x7 ", "100x3"})
    EXPECT_THROW(parseGridSize(bad), std::invalid_argument) << bad;
}

TEST(GridDetection, FindsTheGridWithSubPixelCentres)
{
  EmulatedScreen screen;
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, 10, 45.0, 77);
  std::mt19937 rng(4);
  int found = 0;
  for (const ScreenPose& p : poses)
  {
    const cv::Mat cov = dvs_calibration::testing::renderGridCoverage(screen, p);
    const auto ev = dvs_calibration::testing::emulateEvents(screen, cov, 0, 75000000, rng);
    const GridDetection det = detectCounts(windowOf(ev, 128, 128, 0, 75000000));
    if (!det.found)
      continue;
    ++found;
    ASSERT_EQ(det.centers.size(), 49u);
    EXPECT_GT(orientation(det.centers, screen.grid), 0) << "mirrored order";
    EXPECT_LT(rmsToTruth(det.centers, dvs_calibration::testing::projectCenters(screen, p)), 0.35);
    EXPECT_LT(det.homography_rms_px, 1.5);
  }
  EXPECT_GE(found, 7);
}

TEST(GridDetection, BlinkDetectorFindsTheGridAndIgnoresMovingEdges)
{
  EmulatedScreen screen;
  screen.backlight_flicker = false;
  screen.flicker_hz = 20;
  screen.events_per_log_step = 2.0;
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, 1, 20.0, 8);
  std::mt19937 rng(5);
  const cv::Mat cov = dvs_calibration::testing::renderGridCoverage(screen, poses[0]);
  auto ev = dvs_calibration::testing::emulateEvents(screen, cov, 0, 75000000, rng);
  const EventWindow win = windowOf(ev, 128, 128, 0, 75000000);
  const cv::Mat blinking = blinkingPixels(win, BlinkDetectorConfig());
  GridDetectorConfig cfg;
  const GridDetection det = detectCircleGrid(blinking, win.counts(), 4, cfg);
  ASSERT_TRUE(det.found) << det.reason;
  EXPECT_LT(rmsToTruth(det.centers, dvs_calibration::testing::projectCenters(screen, poses[0])), 0.5);

  // Motion: a bright bar sweeping once across the left half (each pixel: ON at its leading
  // edge, OFF at its trailing edge: one alternation), and a bright region whose edge sweeps over
  // the right half (ON only). Many events, no blinking pixel.
  dvs_driver::EventVector moving;
  for (int x = 0; x < 128; ++x)
    for (int y = 0; y < 128; ++y)
    {
      const int64_t t = (x % 64) * 1000000;
      for (int k = 0; k < 3; ++k)
        moving.push_back({t + k * 1000, static_cast<uint16_t>(x), static_cast<uint16_t>(y), true});
      if (x < 64)
        for (int k = 0; k < 3; ++k)
          moving.push_back({t + 5000000 + k * 1000, static_cast<uint16_t>(x), static_cast<uint16_t>(y), false});
    }
  std::sort(moving.begin(), moving.end(), [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; });
  const EventWindow motion = windowOf(moving, 128, 128, 0, 75000000);
  EXPECT_GT(motion.numEvents(), 70000u);
  EXPECT_EQ(cv::countNonZero(blinkingPixels(motion, BlinkDetectorConfig())), 0);
  // The counts detector sees the swept area as one big blob: no grid either.
  EXPECT_FALSE(detectCounts(motion).found);
}

TEST(GridDetection, RejectsAGridCutByTheImageBorder)
{
  EmulatedScreen screen;
  auto poses = dvs_calibration::testing::calibrationPoses(screen, 1, 10.0, 3);
  std::mt19937 rng(6);
  int tried = 0;
  // Slide the grid out of the image to the left: every shift that puts the leftmost centres
  // within 3 px of the border (circles cut) or beyond it must be rejected.
  for (double shift = 0.0; shift < 0.2; shift += 0.004)
  {
    ScreenPose p = poses[0];
    p.tvec[0] -= shift;
    const auto truth = dvs_calibration::testing::projectCenters(screen, p);
    double min_x = 1e9;
    for (const auto& c : truth)
      min_x = std::min(min_x, static_cast<double>(c.x));
    if (min_x > 3.0 || min_x < -6.0)
      continue;
    ++tried;
    const cv::Mat cov = dvs_calibration::testing::renderGridCoverage(screen, p);
    const auto ev = dvs_calibration::testing::emulateEvents(screen, cov, 0, 75000000, rng);
    const GridDetection det = detectCounts(windowOf(ev, 128, 128, 0, 75000000));
    EXPECT_FALSE(det.found) << "shift " << shift << " leftmost centre x " << min_x;
  }
  EXPECT_GE(tried, 3);
}

TEST(GridDetection, RejectsAnAmbiguousLargerGrid)
{
  // 8 columns shown, 7 expected: any 7 of them would be a wrong correspondence.
  EmulatedScreen screen;
  screen.grid.cols = 8;
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, 4, 20.0, 9);
  std::mt19937 rng(7);
  for (const ScreenPose& p : poses)
  {
    const cv::Mat cov = dvs_calibration::testing::renderGridCoverage(screen, p);
    const auto ev = dvs_calibration::testing::emulateEvents(screen, cov, 0, 75000000, rng);
    const EventWindow win = windowOf(ev, 128, 128, 0, 75000000);
    EXPECT_FALSE(detectCounts(win).found);
    // The same view is found as the 8x7 grid it is.
    GridSize g;
    g.cols = 8;
    EXPECT_TRUE(detectCounts(win, g).found);
  }
}

TEST(GridDetection, NoDetectionOnPureNoise)
{
  EmulatedScreen screen;
  std::mt19937 rng(8);
  for (double rate : {1.0, 10.0, 100.0})
  {
    dvs_driver::EventStream s;
    s.width = s.height = 128;
    s.events = dvs_calibration::testing::emulateNoise(screen, 0, 1000000000, rate, rng);
    for (DetectorKind kind : {DetectorKind::Counts, DetectorKind::Blink})
    {
      size_t windows = 0;
      EXPECT_EQ(sessionDetections(s, kind, &windows), 0u) << "rate " << rate;
      EXPECT_GE(windows, 26u);
    }
  }
}

TEST(GridDetection, NoDetectionOnRealRecordings)
{
  const std::string dir = DVS_REAL_DATA_DIR;
  size_t total_windows = 0;
  for (const char* name : {"ucsd_alex_walking_again.aedat", "colleen_pen_short.aedat", "biolab_caixa_box.aedat",
                           "biolab_dataset2_caixa_negative_ts.aedat", "IMU_rotDisk.aedat"})
  {
    const dvs_driver::AedatRecording rec = dvs_driver::readAedat(dir + "/" + name);
    ASSERT_GT(rec.stream.events.size(), 10000u) << name;
    for (DetectorKind kind : {DetectorKind::Counts, DetectorKind::Blink})
    {
      size_t windows = 0;
      EXPECT_EQ(sessionDetections(rec.stream, kind, &windows), 0u) << name << " " << toString(kind);
      EXPECT_GT(windows, 40u) << name;
      total_windows += windows;
    }
  }
  EXPECT_GT(total_windows, 1000u);
}

TEST(ViewCollector, DistanceIgnoresWhichCornerTheDetectorStartedAt)
{
  EmulatedScreen screen;
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, 2, 30.0, 17);
  const auto a = dvs_calibration::testing::projectCenters(screen, poses[0]);
  const GridSize g;
  // The same view in the three other orders a symmetric square grid allows (rotations by 90 deg
  // of the index grid) and mirrored.
  auto reorder = [&](auto f) {
    std::vector<cv::Point2f> out(a.size());
    for (int r = 0; r < g.rows; ++r)
      for (int c = 0; c < g.cols; ++c)
        out[static_cast<size_t>(r * g.cols + c)] = a[static_cast<size_t>(f(r, c))];
    return out;
  };
  const auto rot90 = reorder([&](int r, int c) { return c * g.cols + (g.cols - 1 - r); });
  const auto rot180 = reorder([&](int r, int c) { return (g.rows - 1 - r) * g.cols + (g.cols - 1 - c); });
  const auto mirror = reorder([&](int r, int c) { return r * g.cols + (g.cols - 1 - c); });
  EXPECT_NEAR(viewDistance(a, a, g), 0.0, 1e-9);
  EXPECT_NEAR(viewDistance(a, rot90, g), 0.0, 1e-5);
  EXPECT_NEAR(viewDistance(a, rot180, g), 0.0, 1e-5);
  EXPECT_NEAR(viewDistance(a, mirror, g), 0.0, 1e-5);
  // A shifted view is as far as the shift.
  auto shifted = a;
  for (auto& p : shifted)
    p += cv::Point2f(5.f, 0.f);
  EXPECT_NEAR(viewDistance(a, shifted, g), 5.0, 1e-4);

  ViewCollectorConfig cfg;
  cfg.min_view_difference_px = 8;
  cfg.max_views = 2;
  ViewCollector views(g, cfg);
  EXPECT_TRUE(views.isNovel(a));
  EXPECT_TRUE(views.add({a, 0}));
  EXPECT_FALSE(views.isNovel(rot180));
  EXPECT_FALSE(views.isNovel(shifted));
  const auto b = dvs_calibration::testing::projectCenters(screen, poses[1]);
  EXPECT_TRUE(views.isNovel(b));
  EXPECT_TRUE(views.add({b, 1}));
  EXPECT_FALSE(views.add({b, 2}));  // full
}

TEST(CalibrationSession, OverlappingWindowsInTimeOrderAndRestartWhenTimeGoesBack)
{
  SessionConfig cfg;
  CalibrationSession session(cfg);
  std::vector<std::pair<int64_t, int64_t>> windows;
  session.setWindowCallback([&](const WindowResult& w) { windows.emplace_back(w.t_begin_ns, w.t_end_ns); });
  dvs_driver::EventVector ev;
  for (int64_t t = 0; t < 300000000; t += 1000000)
    ev.push_back({t, 10, 10, (t / 1000000) % 2 == 0});
  session.addEvents(ev);
  session.flush();
  // Windows of 75 ms every 37.5 ms, reported in order of their end.
  ASSERT_GE(windows.size(), 7u);
  for (size_t i = 0; i < windows.size(); ++i)
  {
    EXPECT_EQ(windows[i].second - windows[i].first, 75000000);
    if (i > 0)
      EXPECT_EQ(windows[i].second - windows[i - 1].second, 37500000) << i;
  }
  EXPECT_EQ(session.windowsProcessed(), windows.size());
  // A replayed recording (time jumps back): new windows start at the new time.
  windows.clear();
  dvs_driver::EventVector again = {{5000000, 1, 1, true}, {200000000, 1, 1, false}};
  session.addEvents(again);
  session.flush();
  ASSERT_FALSE(windows.empty());
  EXPECT_LE(windows.front().first, 5000000);
  EXPECT_EQ(session.detections(), 0u);
}
