#pragma once
// The screen_loop node's parameters: one table (name, field, unit, bounds, documentation; the
// suite's ParamTable, dvs_driver/param_table.h) read from ROS parameters by ScreenLoopRos and
// printed as the README's table. ROS-free.
#include <dvs_driver/param_table.h>
#include <dvs_screen_sim/screen_loop/screen_loop_procedure.h>

#include <string>

namespace dvs_screen_sim
{
namespace screen_loop
{
struct ScreenLoopParams
{
  std::string scenario = "flip";
  std::string config_file;
  std::string calibration_file;
  bool fullscreen = true;
  int width = 1024, height = 768;
  int pattern_cols = 7, pattern_rows = 5;
  double pattern_spacing_x = 0.085, pattern_spacing_y = 0.11;
  double pattern_centre_x = 0.0, pattern_centre_y = 0.0;
  double pattern_radius_px = 11.0;
  int blink_frames = 2;
  double alignment_duration = 0.5;
  int alignment_attempts = 5;
  double max_alignment_residual = 0.5;
  std::string detector = "counts";
  double time_scale = 1.0;
  std::string bag;
  std::string world_frame = "world";
  std::string ground_truth_frame = "dvs_gt";
  int refresh_measurement_frames = 60;
  double monitor_response_time = 0.0;
};

/// The table bound to `p`'s fields (with the cross-parameter rules: window size when not
/// fullscreen, the pattern's layout).
dvs_driver::ParamTable screenLoopParamTable(ScreenLoopParams& p);

/// The procedure's settings from the parameters (the node's alignment: 0.1 s of settling, then
/// alignment_duration of events per attempt; no settling frame before the playback).
ProcedureConfig procedureConfig(const ScreenLoopParams& p);
}  // namespace screen_loop
}  // namespace dvs_screen_sim
