#pragma once
// Rigid poses of the virtual camera. Every pose in this package is T_world_cam: it maps camera
// coordinates (x right, y down, z forward) into the world; `p` is the camera centre in the
// world, `q` the camera's orientation in the world (Hamilton quaternion).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace dvs_screen_sim
{
struct Pose
{
  Eigen::Vector3d p = Eigen::Vector3d::Zero();               ///< camera centre in world [m]
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();     ///< R_world_cam

  Eigen::Matrix3d R_world_cam() const { return q.toRotationMatrix(); }
  /// World point -> camera coordinates.
  Eigen::Vector3d worldToCam(const Eigen::Vector3d& p_world) const { return q.conjugate() * (p_world - p); }
  /// Camera point -> world coordinates.
  Eigen::Vector3d camToWorld(const Eigen::Vector3d& p_cam) const { return q * p_cam + p; }
};

/// A pose with its time [s].
struct StampedPose
{
  double t = 0.0;
  Pose T_world_cam;
};

using PoseTrajectory = std::vector<StampedPose>;

/// The orientation of a camera looking straight at the wall (world plane z = 0) from z > 0,
/// image right = world +x, image up = world +y: R_world_cam = diag(1, -1, -1).
inline Eigen::Quaterniond lookingAtWallOrientation()
{
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  return Eigen::Quaterniond(R);
}
}  // namespace dvs_screen_sim
