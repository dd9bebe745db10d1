// End-to-end verification with the suite's software DVS (dvs_screen_sim), run as an external
// program: a DVS128 with known intrinsics and distortion and realistic noise looks at a screen
// showing the 7x7 grid from 24 poses tilted up to 45 deg, moving between them. Our offline tool
// must recover fx, fy within 1 %, cx, cy within 1.5 px, k1 within 0.03, RMS <= 0.3 px.
#include "sim_scenario.h"

#include <dvs_calibration/calibration_session.h>
#include <dvs_driver/event_text_io.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <sys/stat.h>
#include <sys/wait.h>

using namespace dvs_calibration;
using namespace dvs_calibration::testing;

namespace
{
std::string makeDir(const std::string& name)
{
  const std::string dir = ::testing::TempDir() + "/" + name;
  ::mkdir(dir.c_str(), 0755);
  return dir;
}

void runEndToEnd(const SimScenario& scenario, const std::string& name, const std::string& detector, uint32_t seed)
{
  const std::string simulate = findSimulator(DVS_DEVEL_LIB_DIR);
  ASSERT_FALSE(simulate.empty()) << "dvs_screen_sim's simulate was not found in " << DVS_DEVEL_LIB_DIR
                                 << " (build dvs_screen_sim, or set DVS_SCREEN_SIM_SIMULATE)";
  const std::string dir = makeDir(name);
  const auto poses = orderForShortMoves(scenario.screen, calibrationPoses(scenario.screen, 20, 45.0, seed));
  ASSERT_EQ(poses.size(), 20u);
  const std::string cfg = writeSimScenario(dir, scenario, poses);
  const std::string out = dir + "/sim";
  const std::string sim_cmd = simulate + " --scenario file --out " + out + " --seed " + std::to_string(seed) +
                              " --config " + cfg + " > " + dir + "/simulate.log 2>&1";
  ASSERT_EQ(std::system(sim_cmd.c_str()), 0) << sim_cmd;

  const std::string yaml = dir + "/camera.yaml", json = dir + "/summary.json";
  char spacing[32];
  std::snprintf(spacing, sizeof(spacing), "%.6f", scenario.screen.spacing_m);
  const std::string cal_cmd = std::string(DVS_CALIBRATE_TOOL) + " --events " + out + "/events.txt --grid 7x7 --spacing " +
                              spacing + " --detector " + detector + " --out " + yaml + " > " + json;
  ASSERT_EQ(std::system(cal_cmd.c_str()), 0) << cal_cmd;
  std::ifstream in(json);
  std::string summary;
  std::getline(in, summary);
  std::printf("%s\n", summary.c_str());

  // Truth: the simulator's own camera file.
  const CameraModel truth = loadCameraInfoYaml(out + "/camera_info.yaml");
  const CameraModel est = loadCameraInfoYaml(yaml);
  const CameraIntrinsics& t = truth.intrinsics();
  const CameraIntrinsics& e = est.intrinsics();
  EXPECT_NEAR(t.fx, scenario.screen.camera.intrinsics().fx, 1e-9);  // the scenario reached the simulator
  EXPECT_NEAR(e.fx, t.fx, 0.01 * t.fx) << summary;
  EXPECT_NEAR(e.fy, t.fy, 0.01 * t.fy) << summary;
  EXPECT_NEAR(e.cx, t.cx, 1.5) << summary;
  EXPECT_NEAR(e.cy, t.cy, 1.5) << summary;
  EXPECT_NEAR(e.k1, t.k1, 0.03) << summary;
  const size_t rms_at = summary.find("\"rms_px\":");
  ASSERT_NE(rms_at, std::string::npos);
  EXPECT_LE(std::atof(summary.c_str() + rms_at + 9), 0.3) << summary;
  const size_t used_at = summary.find("\"views_used\":");
  ASSERT_NE(used_at, std::string::npos);
  EXPECT_GE(std::atoi(summary.c_str() + used_at + 13), 12) << summary;
  // The simulated recording is a few hundred MB: keep it only when something failed.
  if (!::testing::Test::HasFailure())
    std::system(("rm -rf '" + dir + "'").c_str());
}
}  // namespace

// A dimmed LED-backlit screen: its white pixels flicker at 200 Hz; thresholded counts.
TEST(SimEndToEnd, FlickeringBacklight200Hz)
{
  SimScenario s;
  runEndToEnd(s, "e2e_flicker", "counts", 31);
}

// A screen that does not flicker: the display program blinks the grid black <-> white at
// 20 Hz; found by the per-pixel ON/OFF timing detector.
TEST(SimEndToEnd, SoftwareBlinkingGridBlinkDetector)
{
  SimScenario s;
  s.backlight_flicker = false;
  s.flicker_hz = 20.0;
  runEndToEnd(s, "e2e_blink_detector", "blink", 33);
}
