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

/// The cross-product matrix: skew(w) v = w x v.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& w)
{
  Eigen::Matrix3d s;
  s << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return s;
}
}  // namespace dvs_line_tracker
