#pragma once
// The tracker's pose is the suite's one pose type (dvs_calibration/pose.h: T_world_camera,
// stored as R_camera_world / t_camera_world); here the solver's fixed-size types beside it.
#include <dvs_calibration/pose.h>

namespace dvs_line_tracker
{
using dvs_calibration::orientationError;
using dvs_calibration::Pose;
using dvs_calibration::positionError;
using dvs_calibration::Vector6d;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix26d = Eigen::Matrix<double, 2, 6>;
}  // namespace dvs_line_tracker
