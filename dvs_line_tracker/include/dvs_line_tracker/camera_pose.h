#pragma once
// The camera pose as the tracker optimises it: T_cam_world (world point -> camera point),
// with helpers to express it as T_world_cam (the published convention) and to apply the
// 6-vector increments of the solvers (left perturbation in the camera frame).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace dvs_line_tracker
{
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix26d = Eigen::Matrix<double, 2, 6>;

struct CameraPose
{
  Eigen::Matrix3d R_cam_world = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_cam_world = Eigen::Vector3d::Zero();

  Eigen::Vector3d toCamera(const Eigen::Vector3d& p_world) const { return R_cam_world * p_world + t_cam_world; }

  /// Camera centre in the world (translation of T_world_cam).
  Eigen::Vector3d positionWorld() const { return -R_cam_world.transpose() * t_cam_world; }
  Eigen::Matrix3d R_world_cam() const { return R_cam_world.transpose(); }
  Eigen::Quaterniond q_world_cam() const { return Eigen::Quaterniond(R_world_cam()).normalized(); }

  static CameraPose fromWorldCam(const Eigen::Matrix3d& R_world_cam, const Eigen::Vector3d& p_world_cam)
  {
    CameraPose pose;
    pose.R_cam_world = R_world_cam.transpose();
    pose.t_cam_world = -pose.R_cam_world * p_world_cam;
    return pose;
  }

  /// p_cam <- exp([w]x) p_cam + v, with delta = (w, v): rotation (rad) then translation (m).
  void applyIncrement(const Vector6d& delta)
  {
    const Eigen::Vector3d w = delta.head<3>();
    const double angle2 = w.squaredNorm();
    Eigen::Matrix3d dR;
    if (angle2 < 1e-4)
    {
      // Per-event increments are tiny: the unit quaternion (1, w/2) normalised, no trigonometry
      // (exact to third order in |w|).
      dR = Eigen::Quaterniond(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized().toRotationMatrix();
    }
    else
    {
      const double angle = std::sqrt(angle2);
      dR = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
    }
    R_cam_world = dR * R_cam_world;
    t_cam_world = dR * t_cam_world + delta.tail<3>();
  }

  /// Re-orthonormalise the rotation (call now and then after many small increments).
  void normalize()
  {
    const Eigen::Quaterniond q(R_cam_world);
    R_cam_world = q.normalized().toRotationMatrix();
  }
};

/// Position error (m) and orientation error (rad, angle of R_a^T R_b) between two poses.
inline double positionError(const CameraPose& a, const CameraPose& b) { return (a.positionWorld() - b.positionWorld()).norm(); }
inline double orientationError(const CameraPose& a, const CameraPose& b)
{
  const Eigen::Matrix3d dR = a.R_world_cam().transpose() * b.R_world_cam();
  const double c = std::max(-1.0, std::min(1.0, (dR.trace() - 1.0) / 2.0));
  return std::acos(c);
}
}  // namespace dvs_line_tracker
