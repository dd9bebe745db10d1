#pragma once
// The calibration node's parameters (ROS-free): the struct, the one table (name, unit, range,
// meaning) the node reads as private ROS parameters and the README shows, and the conversion to
// the session's configuration.
#include <dvs_calibration/calibration_session.h>
#include <dvs_driver/param_table.h>

#include <string>

namespace dvs_calibration
{
struct CalibrationNodeParams
{
  std::string grid = "7x7";       ///< circles, columns x rows
  double spacing_m = 0.03;        ///< centre-to-centre circle distance
  int width = 0, height = 0;      ///< sensor size; 0: from the event messages
  double window_s = 0.075;        ///< integration window
  std::string detector = "counts";
  int count_threshold = 0;
  int closing_size = 3;
  int blink_min_transitions = 2;
  bool auto_collect = true;
  bool start_collecting = true;
  double min_view_difference_px = 8.0;
  double max_motion_px = 0.5;
  int max_views = 200;
  double max_homography_rms_px = 1.5;
  int min_views = 8;
  double outlier_factor = 3.0;
  bool estimate_k3 = false;
  std::string camera_name = "dvs";
  std::string output_file;        ///< "" = $ROS_HOME/camera_info/<camera_name>.yaml
  std::string set_camera_info_service = "dvs/set_camera_info";
  bool call_set_camera_info = true;
  std::string frame_id = "dvs";
  int preview_upscale = 4;
};

dvs_driver::ParamTable calibrationParamTable(CalibrationNodeParams& params);

/// The session configuration of these parameters (the sensor size as given, 0 = unknown yet).
/// Throws std::invalid_argument naming `grid` or `detector` when they do not parse.
SessionConfig toSessionConfig(const CalibrationNodeParams& params);
}  // namespace dvs_calibration
