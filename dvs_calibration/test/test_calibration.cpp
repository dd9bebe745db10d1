// End-to-end calibration on emulated recordings (a DVS128 with distortion in front of a
// flickering or blinking screen) and the calibrator's outlier handling.
#include "emulated_screen.h"

#include <dvs_calibration/calibration_report.h>
#include <dvs_calibration/calibration_session.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_text_io.h>
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>

using namespace dvs_calibration;
using dvs_calibration::testing::EmulatedScreen;

namespace
{
void expectAccurate(const CalibrationResult& r, const CameraModel& truth)
{
  const CameraIntrinsics& e = r.camera.intrinsics();
  const CameraIntrinsics& t = truth.intrinsics();
  std::printf("fx %.3f fy %.3f cx %.3f cy %.3f k1 %.4f k2 %.4f p1 %.5f p2 %.5f rms %.3f views %zu dropped %zu\n", e.fx,
              e.fy, e.cx, e.cy, e.k1, e.k2, e.p1, e.p2, r.rms_px, r.used_views.size(), r.dropped_views.size());
  EXPECT_NEAR(e.fx, t.fx, 0.01 * t.fx);
  EXPECT_NEAR(e.fy, t.fy, 0.01 * t.fy);
  EXPECT_NEAR(e.cx, t.cx, 1.5);
  EXPECT_NEAR(e.cy, t.cy, 1.5);
  EXPECT_NEAR(e.k1, t.k1, 0.03);
  EXPECT_LE(r.rms_px, 0.3);
}

CalibrationResult runSession(const EmulatedScreen& screen, DetectorKind detector, int n_poses, uint32_t seed,
                             size_t* views = nullptr)
{
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, n_poses, 45.0, seed);
  EXPECT_EQ(static_cast<int>(poses.size()), n_poses);
  const auto events = dvs_calibration::testing::emulateRecording(screen, poses, 400000000, 100000000, seed);
  SessionConfig cfg;
  cfg.detector = detector;
  cfg.calibrator.spacing_m = screen.spacing_m;
  CalibrationSession session(cfg);
  session.addEvents(events);
  session.flush();
  if (views)
    *views = session.views().size();
  std::printf("windows %zu detections %zu stable %zu views %zu\n", session.windowsProcessed(), session.detections(),
              session.stableDetections(), session.views().size());
  return session.calibrate();
}
}  // namespace

TEST(Calibration, FlickeringBacklightEndToEnd)
{
  EmulatedScreen screen;
  size_t views = 0;
  const CalibrationResult r = runSession(screen, DetectorKind::Counts, 24, 11, &views);
  EXPECT_GE(views, 20u);
  expectAccurate(r, screen.camera);
}

TEST(Calibration, SoftwareBlinkingGridEndToEnd)
{
  // A normal (non-dimmed) screen: the program blinks the grid black/white at 20 Hz.
  EmulatedScreen screen;
  screen.backlight_flicker = false;
  screen.flicker_hz = 20.0;
  screen.events_per_log_step = 2.0;
  size_t views = 0;
  const CalibrationResult r = runSession(screen, DetectorKind::Counts, 24, 12, &views);
  EXPECT_GE(views, 20u);
  expectAccurate(r, screen.camera);
}

TEST(Calibration, BlinkDetectorEndToEnd)
{
  EmulatedScreen screen;
  screen.backlight_flicker = false;
  screen.flicker_hz = 20.0;
  screen.events_per_log_step = 2.0;
  size_t views = 0;
  const CalibrationResult r = runSession(screen, DetectorKind::Blink, 24, 13, &views);
  EXPECT_GE(views, 20u);
  expectAccurate(r, screen.camera);
}

TEST(Calibration, DropsOutlierViewAndReportsPerViewRms)
{
  EmulatedScreen screen;
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, 12, 40.0, 5);
  std::vector<std::vector<cv::Point2f>> views;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.f, 0.1f);
  for (const auto& p : poses)
  {
    auto c = dvs_calibration::testing::projectCenters(screen, p);
    for (auto& q : c)
      q += cv::Point2f(noise(rng), noise(rng));
    views.push_back(c);
  }
  // View 4: two circles swapped (a wrong correspondence).
  std::swap(views[4][10], views[4][30]);
  CalibratorConfig cfg;
  cfg.spacing_m = screen.spacing_m;
  const CalibrationResult r = calibrateIntrinsics(views, 128, 128, cfg);
  ASSERT_EQ(r.dropped_views.size(), 1u);
  EXPECT_EQ(r.dropped_views[0], 4u);
  EXPECT_EQ(r.used_views.size(), 11u);
  ASSERT_EQ(r.per_view_rms_px.size(), 11u);
  for (double v : r.per_view_rms_px)
    EXPECT_LT(v, 0.3);
  EXPECT_NEAR(r.rms_px, 0.1, 0.05);  // the added noise, 0.1 px per axis ~ RMS of the fit
  EXPECT_NEAR(r.camera.intrinsics().fx, 115.0, 1.0);
}

TEST(Calibration, TooFewViewsIsAnError)
{
  EmulatedScreen screen;
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, 3, 30.0, 5);
  std::vector<std::vector<cv::Point2f>> views;
  for (const auto& p : poses)
    views.push_back(dvs_calibration::testing::projectCenters(screen, p));
  CalibratorConfig cfg;
  cfg.spacing_m = screen.spacing_m;
  EXPECT_THROW(calibrateIntrinsics(views, 128, 128, cfg), CalibrationError);
  cfg.spacing_m = -1;
  EXPECT_THROW(calibrateIntrinsics(views, 128, 128, cfg), std::invalid_argument);
  views.push_back({cv::Point2f(1, 1)});
  cfg.spacing_m = 0.03;
  EXPECT_THROW(calibrateIntrinsics(views, 128, 128, cfg), CalibrationError);
}

TEST(Calibration, SessionRejectsBadParameters)
{
  SessionConfig c;
  c.window_ns = 0;
  EXPECT_THROW(CalibrationSession{c}, std::invalid_argument);
  c = SessionConfig();
  c.calibrator.spacing_m = 0;
  EXPECT_THROW(CalibrationSession{c}, std::invalid_argument);
  c = SessionConfig();
  c.width = -3;
  EXPECT_THROW(CalibrationSession{c}, std::invalid_argument);
  EXPECT_THROW(parseDetectorKind("hough"), std::invalid_argument);
  EXPECT_EQ(parseDetectorKind("blink"), DetectorKind::Blink);
}

TEST(Calibration, JsonSummaryHasTheResult)
{
  EmulatedScreen screen;
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, 8, 40.0, 9);
  std::vector<std::vector<cv::Point2f>> views;
  for (const auto& p : poses)
    views.push_back(dvs_calibration::testing::projectCenters(screen, p));
  CalibratorConfig cfg;
  cfg.spacing_m = screen.spacing_m;
  const CalibrationResult r = calibrateIntrinsics(views, 128, 128, cfg);
  CalibrationSummary s;
  s.views_collected = 8;
  s.result = &r;
  s.output_path = "a\"b.yaml";
  const std::string json = toJson(s);
  EXPECT_NE(json.find("\"views_used\":8"), std::string::npos) << json;
  EXPECT_NE(json.find("\"distortion_model\":\"plumb_bob\""), std::string::npos);
  EXPECT_NE(json.find("\"out\":\"a\\\"b.yaml\""), std::string::npos) << json;
  EXPECT_EQ(json.find('\n'), std::string::npos);
  // Exact projections: the recovered camera is the true one.
  EXPECT_NEAR(r.camera.intrinsics().fx, 115.0, 0.01);
  EXPECT_NEAR(r.camera.intrinsics().k1, -0.12, 1e-3);
  EXPECT_LT(r.rms_px, 1e-3);
}

TEST(Calibration, OfflineToolCalibratesAnEventsFile)
{
  EmulatedScreen screen;
  const auto poses = dvs_calibration::testing::calibrationPoses(screen, 12, 45.0, 21);
  const auto events = dvs_calibration::testing::emulateRecording(screen, poses, 300000000, 100000000, 21);
  const std::string dir = ::testing::TempDir();
  const std::string events_path = dir + "/calib_events.txt", yaml = dir + "/calib_camera.yaml",
                    json = dir + "/calib_summary.json";
  dvs_driver::writeEventsText(events_path, events);
  const std::string cmd = std::string(DVS_CALIBRATE_TOOL) + " --events " + events_path +
                          " --grid 7x7 --spacing 0.03 --out " + yaml + " > " + json;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const CameraModel cam = loadCameraInfoYaml(yaml);
  EXPECT_NEAR(cam.intrinsics().fx, 115.0, 1.15);
  EXPECT_NEAR(cam.intrinsics().cx, 63.5, 1.5);
  std::ifstream in(json);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.rfind("{\"windows\":", 0), 0u) << line;
  EXPECT_NE(line.find("\"rms_px\":"), std::string::npos);
  // The same recording from a bag (1 ms packets, as the driver records them).
  const std::string bag = dir + "/calib_events.bag", yaml_bag = dir + "/calib_camera_bag.yaml";
  dvs_driver::EventStream stream;
  stream.events = events;
  stream.width = stream.height = 128;
  dvs_driver::writeEventsBag(bag, "/dvs/events", stream);
  ASSERT_EQ(std::system((std::string(DVS_CALIBRATE_TOOL) + " --bag " + bag + " --grid 7x7 --spacing 0.03 --out " +
                         yaml_bag + " > /dev/null").c_str()),
            0);
  EXPECT_NEAR(loadCameraInfoYaml(yaml_bag).intrinsics().fx, cam.intrinsics().fx, 1e-6);  // same events, same result
  // A real recording without any grid: exit status 1 and a JSON error, no crash.
  EXPECT_EQ(WEXITSTATUS(std::system((std::string(DVS_CALIBRATE_TOOL) + " --aedat " + DVS_REAL_DATA_DIR +
                                     "/colleen_pen_short.aedat --spacing 0.03 --out " + yaml + " > " + json).c_str())),
            1);
  std::ifstream in2(json);
  std::getline(in2, line);
  EXPECT_NE(line.find("\"error\":"), std::string::npos) << line;
  // Bad input: a clear error and exit status 2, no crash.
  EXPECT_EQ(WEXITSTATUS(std::system((std::string(DVS_CALIBRATE_TOOL) + " --events " + events_path +
                                     " --grid 7y7 --spacing 0.03 --out " + yaml + " 2>/dev/null").c_str())),
            2);
  EXPECT_EQ(WEXITSTATUS(std::system((std::string(DVS_CALIBRATE_TOOL) + " --events /nonexistent.txt --spacing 0.03 --out " +
                                     yaml + " 2>/dev/null").c_str())),
            2);
}
