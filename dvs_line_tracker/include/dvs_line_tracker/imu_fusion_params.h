#pragma once
// The IMU fusion's parameters (issue 17): extrinsics, clock offset, gravity, the IMU's noise
// model (continuous densities, as the software DVS's IMU and Kalibr give them), the vision
// measurement's weight and the health limits under which the IMU is trusted. The rows of the
// tracker's parameter table named `imu_*` are these (tracker_params.cpp).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>
#include <string>

namespace dvs_line_tracker
{
struct ImuFusionParams
{
  /// R_camera_imu as a quaternion "x y z w" (IMU axes -> camera axes) and the IMU's origin in the
  /// camera frame "x y z" [m]. Default: the IMU's axes are the camera's (as DAVIS drivers give them
  /// after their own rotation) at the camera centre.
  std::string q_camera_imu = "0 0 0 1";
  std::string p_camera_imu = "0 0 0";
  /// Gravity in the map (world) frame "x y z" [m/s^2] when known (the square on a wall with world
  /// y up: "0 -9.81 0"); empty: estimated online, started from the first accelerometer samples.
  std::string gravity_world;
  double time_offset_s = 0.0;           ///< t_events = t_imu + time_offset
  double gyro_noise_density = 1.7e-4;   ///< rad/s/sqrt(Hz)
  double gyro_random_walk = 2.0e-5;     ///< rad/s^2/sqrt(Hz)
  double accel_noise_density = 2.0e-3;  ///< m/s^2/sqrt(Hz)
  double accel_random_walk = 3.0e-3;    ///< m/s^3/sqrt(Hz)
  double initial_gyro_bias_sigma = 0.01;   ///< rad/s, prior 1-sigma of the gyroscope bias
  double initial_accel_bias_sigma = 0.05;  ///< m/s^2, prior 1-sigma of the accelerometer bias
  double initial_velocity_sigma = 1.0;     ///< m/s, velocity prior when tracking starts
  double initial_gravity_sigma = 0.5;      ///< m/s^2 per axis, when gravity is estimated
  /// An estimated gravity starts from the specific force of the last 0.2 s, which is tilted when
  /// the camera was accelerating then. Until a second filter with the accelerometer has run this
  /// long with plausible biases (within 2x their prior), the tracker's filter runs without the
  /// accelerometer (gyroscope, constant-velocity position); biases beyond 4x their prior reject
  /// the gravity (gyroscope only until the next start).
  double gravity_check_s = 0.5;
  double update_period_s = 0.001;          ///< vision pose -> filter update period (event time)
  /// The vision pose's covariance is this times the Gauss-Newton estimate (residual variance x
  /// inverse information of the buffered events): the buffers overlap from one update to the
  /// next and their errors are not white, so the raw estimate is far too confident.
  double vision_covariance_scale = 400.0;
  /// The vision's error is not white: what the tracker gets wrong (edge placement, the lines'
  /// geometry) changes slowly with the view, and the filter, which takes 1,000 vision poses a
  /// second, cannot average it away. The reported pose covariance (odometry) is the filter's
  /// plus this x the latest Gauss-Newton covariance (the estimate itself is not affected).
  double vision_error_scale = 1.0;
  double max_latency_s = 0.2;      ///< newest IMU sample older than this at an event: stream late or missing (ROS transport under load lags by 50-100 ms)
  double max_gyro_rad_s = 60.0;    ///< a larger rate is absurd (deg/s given as rad/s?)
  double max_accel_m_s2 = 200.0;   ///< a larger specific force is absurd
  double max_bridge_s = 0.5;       ///< an event-free gap bridged by the IMU alone, at most
};

/// The parsed vectors of ImuFusionParams.
struct ImuExtrinsics
{
  Eigen::Matrix3d R_camera_imu = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_camera_imu = Eigen::Vector3d::Zero();
  std::optional<Eigen::Vector3d> gravity_world;
};

/// Parse the vector parameters; returns "" or a message naming the parameter.
std::string parseImuExtrinsics(const ImuFusionParams& params, ImuExtrinsics& out);
}  // namespace dvs_line_tracker
