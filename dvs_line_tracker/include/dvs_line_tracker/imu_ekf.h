#pragma once
// The IMU filter (ROS-free): an error-state Kalman filter over the IMU's pose, velocity, the
// gyroscope and accelerometer biases and gravity, propagated by the IMU's samples and corrected
// by the line tracker's camera poses (loosely coupled: the tracker's pose, itself predicted by
// this filter, is the measurement). open_vins' split: this is the state with its propagation and
// its one update; the policy (when to update, what to trust) is ImuPropagator's.
//
// Nominal state: q_world_imu, p_world_imu, v_world_imu, b_g, b_a (IMU axes), g_world.
// Error state (18): dp, dv (world), dtheta (IMU axes, R_true = R Exp(dtheta)), db_g, db_a, dg.
// Model: w = gyro - b_g, a_world = R (accel - b_a) + g; white noise and bias random walks with
// the continuous densities of ImuFusionParams. A known gravity has no uncertainty and is never
// corrected; an estimated one also gets a |g| = 9.81 pseudo-measurement at every update.
#include <dvs_line_tracker/imu_fusion_params.h>
#include <dvs_line_tracker/pose_types.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dvs_line_tracker
{
class ImuEkf
{
public:
  static constexpr int kN = 18;
  using VectorNd = Eigen::Matrix<double, kN, 1>;
  using MatrixNd = Eigen::Matrix<double, kN, kN>;
  enum Block
  {
    kP = 0,
    kV = 3,
    kTheta = 6,
    kBg = 9,
    kBa = 12,
    kG = 15
  };

  ImuEkf(const ImuFusionParams& params, const ImuExtrinsics& extrinsics);

  /// What a (re)start keeps of what the filter learned.
  enum class Keep
  {
    kNothing,   ///< biases zero, an estimated gravity from `accel`
    kGyroBias,  ///< the gyroscope bias; accelerometer bias and an estimated gravity start again
    kAll,       ///< biases and an estimated gravity
  };
  /// Start from the camera pose `T_world_camera` at rest-or-unknown velocity (zero, with the prior
  /// sigma). `accel` (IMU axes, the specific force) starts an estimated gravity against it when
  /// it is not kept.
  void start(const Pose& T_world_camera, const Eigen::Vector3d& accel, Keep keep);

  /// Without the accelerometer the translation follows a constant-velocity model (white
  /// acceleration, kUnmodelledAccelDensity): the position and velocity only follow the camera
  /// pose measurements, and nothing of the specific force reaches the orientation or the gyroscope
  /// bias. For an accelerometer side that cannot be trusted (an implausible estimated gravity).
  void useAccelerometer(bool use) { use_accelerometer_ = use; }
  bool usesAccelerometer() const { return use_accelerometer_; }
  static constexpr double kUnmodelledAccelDensity = 5.0;  ///< m/s^2/sqrt(Hz)

  /// Nominal state over dt [s] with the samples held (per event: cheap, no covariance).
  void propagateMean(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double dt);
  /// Covariance over dt [s] at the current nominal state (once per IMU sample interval).
  void propagateCovariance(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double dt);

  /// Correct by a measured camera pose with covariance `cov` over (rotation error in camera axes,
  /// right-multiplied; camera position in the world). Returns the innovation's squared
  /// Mahalanobis distance (6 degrees of freedom); when it exceeds `gate` nothing is changed.
  double updateCameraPose(const Pose& measured, const Matrix6d& cov, double gate);

  /// The camera's pose (T_world_camera) from the IMU's.
  Pose cameraPose() const;

  /// The camera increment (applyCameraIncrement's delta) of the nominal motion from `from_s` to
  /// `to_s` seconds after the mean's time, the sample held (what propagateMean(gyro, accel, t)
  /// would do to the camera pose between those times), for a camera whose rotation at `from_s`
  /// is `R_camera_world`: the per-event motion without propagating the mean. The rotation is
  /// exact; the translation too for turns beyond 0.01 rad, below to second order in the turn
  /// (of the camera axes and of the lever arm; 1e-11 m at 2000 deg/s, 0.1 ms, a 6 cm arm).
  Vector6d cameraIncrement(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double from_s, double to_s,
                           const Eigen::Matrix3d& R_camera_world) const;

  /// Camera angular velocity (camera axes, rad/s) and camera-centre velocity (world, m/s) for
  /// the latest gyro sample (bias removed).
  Eigen::Vector3d cameraAngularVelocity(const Eigen::Vector3d& gyro) const;
  Eigen::Vector3d cameraVelocityWorld(const Eigen::Vector3d& gyro) const;
  /// Covariance of (rotation error in camera axes, camera position in the world).
  Matrix6d cameraPoseCovariance() const;
  /// Covariance of the camera-centre velocity (world) and of the angular velocity (camera axes),
  /// the latter from the gyro's white noise over `dt` and its bias.
  Eigen::Matrix3d cameraVelocityCovariance() const;
  Eigen::Matrix3d cameraAngularVelocityCovariance(double sample_period_s) const;

  const Eigen::Vector3d& gyroBias() const { return bg_; }
  const Eigen::Vector3d& accelBias() const { return ba_; }
  const Eigen::Vector3d& gravity() const { return g_; }
  const Eigen::Vector3d& velocity() const { return v_; }
  const MatrixNd& covariance() const { return P_; }
  bool started() const { return started_; }

private:
  void inject(const VectorNd& dx);
  /// P H^T and S0 = H P H^T of the camera pose measurement, by H's three 3x3 blocks (rotation
  /// row: R_camera_imu at theta; position row: identity at p, -R_world_imu [p_imu_camera]x at theta).
  void poseMeasurementProducts(Eigen::Matrix<double, kN, 6>& PHt, Matrix6d& HPHt) const;

  const ImuFusionParams* params_;  // pointers, not references: filters are assigned (ImuPropagator's gravity check)
  const ImuExtrinsics* x_;
  Eigen::Matrix3d R_imu_camera_;
  Eigen::Vector3d p_imu_camera_;  ///< camera centre in IMU axes
  Eigen::Quaterniond q_;          ///< q_world_imu
  Eigen::Vector3d p_, v_, bg_, ba_, g_;
  MatrixNd P_;
  bool use_accelerometer_ = true;
  bool started_ = false;
};

/// The camera increment (applyCameraIncrement's delta = (w, v)) that takes `from` to `to`.
Vector6d cameraIncrementBetween(const Pose& from, const Pose& to);
}  // namespace dvs_line_tracker
