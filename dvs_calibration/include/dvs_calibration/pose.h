#pragma once
// The suite's one pose type: T_world_camera, the camera's pose in the world (camera frame x
// right, y down, z forward). Stored as its inverse (R_camera_world, t_camera_world: world point
// -> camera point) because projecting map points is what the tracker does per event; every
// accessor says which way it maps. Also the stamped pose and trajectory, and the two error
// measures every accuracy figure of the suite uses.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dvs_calibration
{
using Vector6d = Eigen::Matrix<double, 6, 1>;

struct Pose
{
  Eigen::Matrix3d R_camera_world = Eigen::Matrix3d::Identity();  ///< world direction -> camera direction
  Eigen::Vector3d t_camera_world = Eigen::Vector3d::Zero();      ///< the world origin in the camera frame

  /// From T_world_camera: orientation R_world_camera (or q_world_camera) and camera centre p_world_camera.
  static Pose fromWorldCamera(const Eigen::Matrix3d& R_world_camera, const Eigen::Vector3d& p_world_camera)
  {
    Pose pose;
    pose.R_camera_world = R_world_camera.transpose();
    pose.t_camera_world = -pose.R_camera_world * p_world_camera;
    return pose;
  }
  static Pose fromWorldCamera(const Eigen::Quaterniond& q_world_camera, const Eigen::Vector3d& p_world_camera)
  {
    return fromWorldCamera(q_world_camera.normalized().toRotationMatrix(), p_world_camera);
  }

  /// World point -> camera coordinates.
  Eigen::Vector3d toCamera(const Eigen::Vector3d& p_world) const { return R_camera_world * p_world + t_camera_world; }
  /// Camera point -> world coordinates.
  Eigen::Vector3d toWorld(const Eigen::Vector3d& p_camera) const
  {
    return R_camera_world.transpose() * (p_camera - t_camera_world);
  }
  /// Camera centre in the world (translation of T_world_camera).
  Eigen::Vector3d p_world_camera() const { return -R_camera_world.transpose() * t_camera_world; }
  Eigen::Matrix3d R_world_camera() const { return R_camera_world.transpose(); }
  Eigen::Quaterniond q_world_camera() const { return Eigen::Quaterniond(R_world_camera()).normalized(); }

  /// Left perturbation in the camera frame, the solvers' increment delta = (w, v) (rad, m):
  /// p_camera <- exp([w]x) p_camera + v.
  void applyCameraIncrement(const Vector6d& delta)
  {
    const Eigen::Vector3d w = delta.head<3>();
    const double angle2 = w.squaredNorm();
    Eigen::Matrix3d dR;
    if (angle2 < 1e-4)
    {
      // Per-event increments are tiny: the rotation of the quaternion (1, v), v = w/2,
      // normalised (exact to third order in |w|), without trigonometry or a square root:
      // ((1 - v.v) I + 2 v v^T + 2 [v]x) / (1 + v.v).
      const Eigen::Vector3d v = 0.5 * w;
      const double vv = v.squaredNorm();
      const double s = 1.0 / (1.0 + vv);
      const double d = (1.0 - vv) * s, s2 = 2.0 * s;
      const double xx = s2 * v.x() * v.x(), yy = s2 * v.y() * v.y(), zz = s2 * v.z() * v.z();
      const double xy = s2 * v.x() * v.y(), xz = s2 * v.x() * v.z(), yz = s2 * v.y() * v.z();
      const double sx = s2 * v.x(), sy = s2 * v.y(), sz = s2 * v.z();
      dR << d + xx, xy - sz, xz + sy,  //
          xy + sz, d + yy, yz - sx,    //
          xz - sy, yz + sx, d + zz;
    }
    else
    {
      const double angle = std::sqrt(angle2);
      dR = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
    }
    R_camera_world = dR * R_camera_world;
    t_camera_world = dR * t_camera_world + delta.tail<3>();
  }

  /// Re-orthonormalise the rotation (now and then after many small increments).
  void normalize() { R_camera_world = Eigen::Quaterniond(R_camera_world).normalized().toRotationMatrix(); }

  bool allFinite() const { return R_camera_world.allFinite() && t_camera_world.allFinite(); }
};

/// A camera at `p_world` looking at `target_world`, the image's "up" (-y) towards `up_world`,
/// rolled by `roll_rad` about the optical axis.
inline Pose lookAt(const Eigen::Vector3d& p_world, const Eigen::Vector3d& target_world, const Eigen::Vector3d& up_world,
                   double roll_rad = 0.0)
{
  const Eigen::Vector3d z = (target_world - p_world).normalized();
  const Eigen::Vector3d x = (-up_world).cross(z).normalized();  // camera y points down (-up)
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R_world_camera;
  R_world_camera.col(0) = x;
  R_world_camera.col(1) = y;
  R_world_camera.col(2) = z;
  R_world_camera = R_world_camera * Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return Pose::fromWorldCamera(R_world_camera, p_world);
}

/// Distance of the camera centres (m).
inline double positionError(const Pose& a, const Pose& b) { return (a.p_world_camera() - b.p_world_camera()).norm(); }
/// Angle (rad) of R_a^T R_b, the orientation difference.
inline double orientationError(const Pose& a, const Pose& b)
{
  const Eigen::Matrix3d dR = a.R_camera_world * b.R_world_camera();
  const double c = std::max(-1.0, std::min(1.0, (dR.trace() - 1.0) / 2.0));
  return std::acos(c);
}

/// A pose with its time (s).
struct StampedPose
{
  double t = 0.0;
  Pose T_world_camera;
};
using Trajectory = std::vector<StampedPose>;
}  // namespace dvs_calibration
