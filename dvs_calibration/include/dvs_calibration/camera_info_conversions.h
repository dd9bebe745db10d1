#pragma once
// The camera model <-> sensor_msgs/CameraInfo, in one place for the whole suite (library
// dvs_calibration_ros): the simulator and the calibration publish camera_info with it, the
// tracker reads camera_info with it.
#include <dvs_calibration/camera_model.h>
#include <sensor_msgs/CameraInfo.h>

#include <string>

namespace dvs_calibration
{
/// camera_info message of a camera model (plumb_bob, R = I, P = [K | 0]).
sensor_msgs::CameraInfo toCameraInfoMsg(const CameraModel& camera, const std::string& frame_id);

/// Camera model of a camera_info message (K and plumb_bob D; an empty D = no distortion).
/// Throws CameraModelError for another distortion model or invalid intrinsics.
CameraModel cameraFromCameraInfo(const sensor_msgs::CameraInfo& info);
}  // namespace dvs_calibration
