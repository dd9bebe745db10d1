#pragma once
// Odometry of a body frame rigidly attached to the camera (a flight controller's base_link), from
// the tracker's camera estimate (ROS-free; the conventions of nav_msgs/Odometry, REP 103/105):
//  - pose: T_world_body = T_world_camera T_camera_body, with covariance over (position in the
//    world, rotation error about the world axes), in that order;
//  - twist: linear and angular velocity of the body expressed in the body frame, with covariance
//    over (linear, angular).
#include <dvs_line_tracker/imu_propagator.h>
#include <dvs_line_tracker/pose_types.h>

#include <string>

namespace dvs_line_tracker
{
struct BodyOdometry
{
  int64_t t_ns = 0;
  Pose T_world_body;  ///< stored as the suite's pose type: "camera" read as "body"
  Matrix6d pose_covariance = Matrix6d::Zero();
  Eigen::Vector3d linear_velocity_body = Eigen::Vector3d::Zero(), angular_velocity_body = Eigen::Vector3d::Zero();
  Matrix6d twist_covariance = Matrix6d::Zero();
  bool has_twist = false;  ///< false: vision only, the twist is unknown (zero, covariance kUnknownVariance)
};

/// Variance written where nothing is known (a twist without IMU).
constexpr double kUnknownVariance = 1e6;
/// Vision alone (no IMU): the odometry's pose covariance is the Gauss-Newton estimate
/// (visionPoseCovariance) times this, measured on the flips of benchmark_imu_fusion (x1 put
/// 46-54 % of the errors inside 1 sigma, x2 the figures in BENCHMARKS.md).
constexpr double kVisionOnlyCovarianceScale = 2.0;

/// T_camera_body from the body's pose of the camera ("x y z w" quaternion R_body_camera and the
/// camera's origin "x y z" [m] in the body frame); returns "" or a message naming the parameter.
std::string parseBodyCameraExtrinsic(const std::string& q_body_camera, const std::string& p_body_camera,
                                     Pose& T_camera_body);

/// The IMU filter's estimate as the body's odometry.
BodyOdometry toBodyOdometry(const ImuOdometry& camera, const Pose& T_camera_body);
/// Vision alone: the tracker's pose with its covariance (rotation in camera axes, position in the
/// world), the twist unknown.
BodyOdometry visionBodyOdometry(int64_t t_ns, const Pose& T_world_camera, const Matrix6d& camera_covariance,
                                const Pose& T_camera_body);
}  // namespace dvs_line_tracker
