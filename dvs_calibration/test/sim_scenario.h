#pragma once
// Writes a scenario for the suite's software DVS (dvs_screen_sim, run as an external program:
// dvs_calibration must not depend on it) that shows the calibration grid on a screen and
// dwells at calibration poses, and finds the simulator's `simulate` program.
#include "emulated_screen.h"

#include <string>
#include <vector>

namespace dvs_calibration
{
namespace testing
{
struct SimScenario
{
  /// Circles: 7x7, spacing, radius fraction, camera (the truth), as in EmulatedScreen.
  EmulatedScreen screen;
  /// true: white circles flicker (dimmed LED backlight) at flicker_hz between flicker_low and
  /// white; false: the program blinks the grid black <-> white at flicker_hz (square wave).
  bool backlight_flicker = true;
  double flicker_hz = 200.0;
  double white = 0.9;
  /// log step 0.69 > 2 C (C = 0.3): a pixel fires on every toggle (a step below 2 C lets the
  /// simulator's deterministic pixels settle where they no longer fire).
  double flicker_low = 0.45;
  double black = 0.02;
  double wall = 0.1;  ///< the wall around the screen
  double dwell_s = 0.25;
  double move_s = 0.15;
  std::string noise_preset = "realistic";
};

/// Write `dir`/config.yaml and `dir`/trajectory.txt (TUM, T_world_camera) for the poses; returns
/// the config path. The world is the simulator's wall (x right, y up, z towards the camera).
std::string writeSimScenario(const std::string& dir, const SimScenario& scenario, const std::vector<ScreenPose>& poses);

/// The poses reordered (greedy nearest neighbour on the projected grid) so that the moves
/// between them are short: fewer motion events, a faster simulation.
std::vector<ScreenPose> orderForShortMoves(const EmulatedScreen& screen, const std::vector<ScreenPose>& poses);

/// The path of dvs_screen_sim's `simulate`: $DVS_SCREEN_SIM_SIMULATE if set, else
/// <devel_lib_dir>/dvs_screen_sim/simulate, else the first dvs_screen_sim/simulate under the
/// lib directories of $CMAKE_PREFIX_PATH. Empty when not found.
std::string findSimulator(const std::string& devel_lib_dir);
}  // namespace testing
}  // namespace dvs_calibration
