#pragma once
// The tracker's pose is the suite's one pose type (dvs_calibration/pose.h: T_world_camera,
// stored as R_camera_world / t_camera_world); here the solver's fixed-size types beside it.
#include <dvs_calibration/pose.h>

#include <cmath>

namespace dvs_line_tracker
{
using dvs_calibration::orientationError;
using dvs_calibration::Pose;
using dvs_calibration::positionError;
using dvs_calibration::Vector6d;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// `pose` agrees with `reference`: its position within `position_ratio` of the reference's
/// distance from the world origin, its orientation within `angle_deg`.
inline bool posesAgree(const Pose& pose, const Pose& reference, double position_ratio, double angle_deg)
{
  return positionError(pose, reference) < position_ratio * reference.p_world_camera().norm() &&
         orientationError(pose, reference) < angle_deg * M_PI / 180;
}

/// The roll (rotation about the camera's optical axis) from `from` to `to` over `dt_s` seconds,
/// as a rate in deg/s (signed; the z component of the relative rotation vector, camera frame).
inline double rollRateDegS(const Pose& from, const Pose& to, double dt_s)
{
  const Eigen::AngleAxisd relative(Eigen::Matrix3d(from.R_camera_world * to.R_world_camera()));
  return relative.angle() * relative.axis().z() * 180 / M_PI / dt_s;
}

/// The cross-product matrix: skew(w) v = w x v.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& w)
{
  Eigen::Matrix3d s;
  s << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return s;
}
}  // namespace dvs_line_tracker
