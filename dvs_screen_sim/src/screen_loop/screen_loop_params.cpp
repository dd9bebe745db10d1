#include <dvs_screen_sim/screen_loop/screen_loop_params.h>
#include <dvs_screen_sim/sim_config.h>

#include <stdexcept>

namespace dvs_screen_sim
{
namespace screen_loop
{
namespace
{
AlignmentPattern pattern(const ScreenLoopParams& p)
{
  AlignmentPattern a;
  a.cols = p.pattern_cols;
  a.rows = p.pattern_rows;
  a.spacing_vp = {p.pattern_spacing_x, p.pattern_spacing_y};
  a.centre_vp = {p.pattern_centre_x, p.pattern_centre_y};
  a.radius_px = p.pattern_radius_px;
  a.blink_frames = p.blink_frames;
  return a;
}
}  // namespace

dvs_driver::ParamTable screenLoopParamTable(ScreenLoopParams& p)
{
  dvs_driver::ParamTable t("screen_loop");
  t.add("scenario", p.scenario, scenarioNames(), "the simulator scenario (scene, trajectory, camera) to play");
  t.add("config_file", p.config_file, {}, "simulator configuration overrides (YAML, keys as for `simulate`)");
  t.add("calibration_file", p.calibration_file, {},
        "the DVS's intrinsics (calib.txt or camera_info YAML, dvs_calibration); empty: the configuration's camera");
  t.add("fullscreen", p.fullscreen, "fullscreen window on the X screen");
  t.add("width", p.width, "px", 1, 100000, "window width when not fullscreen (> 16)");
  t.add("height", p.height, "px", 1, 100000, "window height when not fullscreen (> 16)");
  t.add("pattern_cols", p.pattern_cols, "", 2, 100, "alignment circles per row");
  t.add("pattern_rows", p.pattern_rows, "", 2, 100, "alignment circle rows");
  t.add("pattern_spacing_x", p.pattern_spacing_x, "viewport", 0, 2, "horizontal spacing of the circles").min_exclusive =
      true;
  t.add("pattern_spacing_y", p.pattern_spacing_y, "viewport", 0, 2, "vertical spacing of the circles").min_exclusive =
      true;
  t.add("pattern_centre_x", p.pattern_centre_x, "viewport", -1, 1, "grid centre, x");
  t.add("pattern_centre_y", p.pattern_centre_y, "viewport", -1, 1, "grid centre, y");
  t.add("pattern_radius_px", p.pattern_radius_px, "px", 0, 1000, "circle radius on the screen").min_exclusive = true;
  t.add("blink_frames", p.blink_frames, "refreshes", 1, 1000, "refreshes per half blink period");
  t.add("alignment_duration", p.alignment_duration, "s", 0.05, 60, "events per alignment attempt (after 0.1 s settling)")
      .min_exclusive = true;
  t.add("alignment_attempts", p.alignment_attempts, "", 1, 1000, "alignment attempts before giving up");
  t.add("max_alignment_residual", p.max_alignment_residual, "px", 0, 100,
        "refuse (and retry) alignments with a larger RMS residual")
      .min_exclusive = true;
  t.add("detector", p.detector, {"counts", "blink"}, "circle detector (dvs_calibration): `counts` or `blink`");
  t.add("time_scale", p.time_scale, "", 0, 1e308, "playback this many times slower than the trajectory (thesis: 5)")
      .min_exclusive = true;
  t.add("bag", p.bag, {}, "record events + ground truth (time stamps rescaled to trajectory time) to this bag");
  t.add("world_frame", p.world_frame, {}, "frame of the ground truth");
  t.add("ground_truth_frame", p.ground_truth_frame, {}, "TF child frame of the ground truth");
  t.add("refresh_measurement_frames", p.refresh_measurement_frames, "refreshes", 3, 100000,
        "frames for the refresh-period measurement");
  t.add("monitor_response_time", p.monitor_response_time, "s", 0, 0.1,
        "the monitor's pixel response time (< 0.1; ground truth stamped half of it later)");
  t.addRule([&p]() -> std::string {
    if (!p.fullscreen && !(p.width > 16 && p.height > 16))
      return "~width and ~height must be > 16 when ~fullscreen is false";
    return "";
  });
  t.addRule([&p]() -> std::string {
    try
    {
      pattern(p).validate();
    }
    catch (const std::invalid_argument& e)
    {
      return std::string("~pattern_*: ") + e.what();
    }
    return "";
  });
  t.addRule([&p]() -> std::string {
    return p.monitor_response_time < 0.1 ? "" : "~monitor_response_time must be < 0.1 s";
  });
  t.addRule([&p]() -> std::string {
    return p.world_frame.empty() || p.ground_truth_frame.empty() ? "~world_frame and ~ground_truth_frame must not be empty"
                                                                 : "";
  });
  return t;
}

ProcedureConfig procedureConfig(const ScreenLoopParams& p)
{
  ProcedureConfig c;
  c.pattern = pattern(p);
  c.detector.detector = dvs_calibration::parseDetectorKind(p.detector);
  c.alignment_settle = 0.1;
  c.alignment_duration = p.alignment_duration;
  c.alignment_attempts = p.alignment_attempts;
  c.max_alignment_residual = p.max_alignment_residual;
  c.response_time = p.monitor_response_time;
  c.settle_frames = 0;
  return c;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
