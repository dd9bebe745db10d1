#pragma once
// The one-line JSON summary of a calibration (printed by the offline tool, logged by the node).
#include <dvs_calibration/intrinsic_calibrator.h>

#include <string>

namespace dvs_calibration
{
struct CalibrationSummary
{
  size_t windows = 0;           ///< integration windows processed
  size_t detections = 0;        ///< windows in which the grid was found
  size_t views_collected = 0;   ///< views kept for calibration
  const CalibrationResult* result = nullptr;  ///< null: not calibrated
  std::string error;            ///< why not calibrated
  std::string output_path;
};

/// {"windows":..,"detections":..,"views_collected":..,"views_used":..,"views_dropped":..,
///  "rms_px":..,"per_view_rms_px":[..],"width":..,"height":..,"fx":..,"fy":..,"cx":..,"cy":..,
///  "distortion_model":"plumb_bob","distortion":[k1,k2,p1,p2,k3],"out":".."} or with "error".
std::string toJson(const CalibrationSummary& summary);
}  // namespace dvs_calibration
