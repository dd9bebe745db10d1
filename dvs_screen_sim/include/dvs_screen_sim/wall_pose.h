#pragma once
// Poses in dvs_screen_sim's world: the suite's one pose type (dvs_calibration::Pose,
// T_world_camera; stamped poses and trajectories, dvs_calibration::Trajectory) named in this
// package's namespace, and the reference orientation of its scenes (a camera looking at the wall).
//
// World frame of the simulated scenes: the wall is the plane z = 0, world x points right and
// world y up on the wall, z out of the wall towards the camera.
#include <dvs_calibration/pose.h>

#include <Eigen/Geometry>

namespace dvs_screen_sim
{
using dvs_calibration::Pose;
using dvs_calibration::StampedPose;

/// The orientation of a camera looking straight at the wall (world plane z = 0) from z > 0,
/// image right = world +x, image up = world +y: R_world_camera = diag(1, -1, -1).
inline Eigen::Quaterniond lookingAtWallOrientation()
{
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  return Eigen::Quaterniond(R);
}
}  // namespace dvs_screen_sim
