#include <dvs_calibration/calibration_node_params.h>
#include <dvs_calibration/camera_model.h>

#include <stdexcept>

namespace dvs_calibration
{
dvs_driver::ParamTable calibrationParamTable(CalibrationNodeParams& p)
{
  dvs_driver::ParamTable t("dvs_calibration");
  t.add("grid", p.grid, {}, "circles, columns x rows (2..64 each), e.g. `7x7`");
  t.add("spacing", p.spacing_m, "m", 0, 10, "centre-to-centre circle distance (from `show_pattern`); only scales the poses")
      .min_exclusive = true;
  t.add("width", p.width, "px", 0, kMaxSensorSide, "sensor width; 0 = from the event messages (128 if they say 0)");
  t.add("height", p.height, "px", 0, kMaxSensorSide, "sensor height; 0 = from the event messages");
  t.add("window", p.window_s, "s", 0.001, 10, "integration window (`window_ms`, in ms, is read with a deprecation warning)");
  t.add("detector", p.detector, {"counts", "blink"}, "`counts` (threshold + closing, thesis) or `blink` (ON/OFF alternation)");
  t.add("count_threshold", p.count_threshold, "events", 0, 1000000,
        "events per pixel and window for a white pixel; 0 = automatic (0.25 x 99th percentile, >= 3)");
  t.add("closing_size", p.closing_size, "px", 0, 15, "structuring element of the morphological closing (<= 1: none)");
  t.add("blink_min_transitions", p.blink_min_transitions, "", 1, 1000, "ON<->OFF alternations a blinking pixel needs per window");
  t.add("auto_collect", p.auto_collect, "keep views automatically when new enough");
  t.add("start_collecting", p.start_collecting, "keep views from the start (else after `~start`)");
  t.add("min_view_difference", p.min_view_difference_px, "px", 0, 1e6,
        "a view is new when its outer corners moved this much from every kept view");
  t.add("max_motion", p.max_motion_px, "px", 0, 1e6, "a view is kept only if the grid moved less than this since the previous window")
      .min_exclusive = true;
  t.add("max_views", p.max_views, "", 1, 100000, "views kept at most");
  t.add("max_homography_rms", p.max_homography_rms_px, "px", 0, 1e6, "grids less regular than this (motion, wrong order) are rejected")
      .min_exclusive = true;
  t.add("min_views", p.min_views, "", 3, 100000, "fewer views: `~calibrate` fails");
  t.add("outlier_factor", p.outlier_factor, "", 1, 1e6, "drop views with RMS > factor x median (and > 0.5 px)").min_exclusive = true;
  t.add("estimate_k3", p.estimate_k3, "also estimate k3 (else fixed at 0)");
  t.add("camera_name", p.camera_name, {}, "camera_name in the YAML");
  t.add("output_file", p.output_file, {}, "YAML path for `~save`; empty = `$ROS_HOME/camera_info/<camera_name>.yaml`");
  t.add("set_camera_info_service", p.set_camera_info_service, {}, "service to send the calibration to");
  t.add("call_set_camera_info", p.call_set_camera_info, "call it after `~calibrate`");
  t.add("frame_id", p.frame_id, {}, "frame of the images when the events carry none");
  t.add("preview_upscale", p.preview_upscale, "", 1, 16, "preview magnification");
  t.addRule([&p]() -> std::string {
    return (p.width == 0) == (p.height == 0) ? "" : "width and height must both be 0 (from the events) or both positive";
  });
  t.addRule([&p]() -> std::string { return p.camera_name.empty() ? "camera_name must not be empty" : ""; });
  t.addRule([&p]() -> std::string {
    return p.set_camera_info_service.empty() ? "set_camera_info_service must not be empty" : "";
  });
  t.addRule([&p]() -> std::string {
    try
    {
      parseGridSize(p.grid);
      return "";
    }
    catch (const std::exception& e)
    {
      return std::string("grid: ") + e.what();
    }
  });
  return t;
}

SessionConfig toSessionConfig(const CalibrationNodeParams& p)
{
  SessionConfig c;
  try
  {
    c.grid.grid = parseGridSize(p.grid);
  }
  catch (const std::exception& e)
  {
    throw std::invalid_argument(std::string("grid: ") + e.what());
  }
  try
  {
    c.detector = parseDetectorKind(p.detector);
  }
  catch (const std::exception& e)
  {
    throw std::invalid_argument(std::string("detector: ") + e.what());
  }
  c.width = p.width;
  c.height = p.height;
  c.window_ns = static_cast<int64_t>(p.window_s * 1e9 + 0.5);
  c.threshold.count_threshold = p.count_threshold;
  c.threshold.closing_size = p.closing_size;
  c.blink.closing_size = p.closing_size;
  c.blink.min_transitions = p.blink_min_transitions;
  c.auto_collect = p.auto_collect;
  c.views.min_view_difference_px = p.min_view_difference_px;
  c.views.max_views = static_cast<size_t>(p.max_views);
  c.max_motion_px = p.max_motion_px;
  c.grid.max_homography_rms_px = p.max_homography_rms_px;
  c.calibrator.spacing_m = p.spacing_m;
  c.calibrator.min_views = static_cast<size_t>(p.min_views);
  c.calibrator.outlier_factor = p.outlier_factor;
  c.calibrator.estimate_k3 = p.estimate_k3;
  return c;
}
}  // namespace dvs_calibration
