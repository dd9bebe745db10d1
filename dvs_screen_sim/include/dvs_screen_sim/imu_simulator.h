#pragma once
// The software DVS's IMU (ROS-free, the one home of the IMU model): samples of a 6-axis IMU
// rigidly attached to the simulated camera, from the same continuous trajectory the events come
// from (trajectory.h: poseAt(t) = T_world_camera).
//
//   angular velocity   w_imu = body rate of R_world_imu = R_world_camera R_camera_imu
//   specific force     f_imu = R_imu_world (a_world - g_world),  a_world = d2/dt2 of the IMU's
//                      position p_world_camera + R_world_camera p_camera_imu
// both by central differences of poseAt (step 0.1 ms: errors ~1e-6 for the suite's motions),
// taken inside the run's time range: at its ends they are one-sided (0.1 ms off centre), so the
// trajectories' held end poses (a velocity jump at t = 0 for the helix and the linear motion)
// do not put an impulse into the first and last samples.
// A still camera reads +|g| against gravity (with the default g_world = (0, -9.81, 0), world y up
// on the wall: specific force = +9.81 along world +y, i.e. (0, -9.81, 0) in a camera looking at
// the wall, whose y points down).
//
// Noise (the discrete form of the continuous model of Kalibr / the ETH IMU noise model), per axis
// and sample, dt = 1 / rate:
//   measurement_k = true_k + b_k + sigma_d n_k,      sigma_d = noise_density / sqrt(dt)
//   b_{k+1}       = b_k + sigma_b m_k,               sigma_b = random_walk * sqrt(dt)
// n, m standard normal from one generator seeded by the configuration's seed (its own stream:
// the events are the same with or without the IMU). Initial biases: given, or drawn uniformly in
// direction with a magnitude uniform in [0, initial_*_bias_max].
#include <dvs_driver/imu_sample.h>
#include <dvs_driver/param_table.h>
#include <dvs_screen_sim/trajectory.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <optional>
#include <random>
#include <vector>

namespace dvs_screen_sim
{
struct ImuSimParams
{
  double rate = 1000.0;                  ///< samples per second [Hz]
  double gyro_noise_density = 1.7e-4;    ///< [rad/s/sqrt(Hz)] (MPU-6150 class)
  double gyro_random_walk = 2.0e-5;      ///< gyro bias random walk [rad/s^2/sqrt(Hz)]
  double accel_noise_density = 2.0e-3;   ///< [m/s^2/sqrt(Hz)]
  double accel_random_walk = 3.0e-3;     ///< accel bias random walk [m/s^3/sqrt(Hz)]
  double initial_gyro_bias_max = 0.01;   ///< [rad/s] bound of the random initial gyro bias
  double initial_accel_bias_max = 0.05;  ///< [m/s^2] bound of the random initial accel bias
  std::optional<Eigen::Vector3d> initial_gyro_bias;   ///< [rad/s], IMU axes; unset: random
  std::optional<Eigen::Vector3d> initial_accel_bias;  ///< [m/s^2], IMU axes; unset: random
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};           ///< g in the world frame [m/s^2]
  Eigen::Quaterniond q_camera_imu = Eigen::Quaterniond::Identity();  ///< R_camera_imu (IMU axes -> camera axes)
  Eigen::Vector3d p_camera_imu = Eigen::Vector3d::Zero();            ///< the IMU's origin in the camera frame [m]

  /// The sample period's discrete white-noise standard deviations (density / sqrt(dt)).
  double gyroSigma() const;
  double accelSigma() const;
  /// Throws std::invalid_argument naming the parameter (`imu.<name>`).
  void validate() const;
};

/// The scalar parameters (YAML `imu.<name>`): names, units, bounds, documentation; the README's
/// table is what this prints. The vectors (gravity, extrinsics, initial biases) are validated by
/// ImuSimParams::validate.
dvs_driver::ParamTable imuParamTable(ImuSimParams& p);

/// Noise-free IMU axes' angular velocity [rad/s] and specific force [m/s^2] at t [s].
struct ImuTruth
{
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
};
/// The differences use only times in [t_begin, t_end] (when that is longer than 0.2 ms).
ImuTruth idealImu(const Trajectory& trajectory, double t, const ImuSimParams& params,
                  double t_begin = -std::numeric_limits<double>::infinity(),
                  double t_end = std::numeric_limits<double>::infinity());

/// Streaming generator: sample k at simulated time k / rate, stamped offset_ns + round(k 1e9 / rate).
class ImuSimulator
{
public:
  /// Draws the initial biases (unless given) from `seed`'s IMU stream.
  ImuSimulator(const ImuSimParams& params, uint64_t seed);

  /// Append every sample not yet generated with time <= t [s] (simulated time) to `out`, and,
  /// when `biases` is given, the true biases in force at each (accel = accelerometer bias,
  /// gyro = gyroscope bias, same stamps).
  void advanceTo(const Trajectory& trajectory, double t, int64_t offset_ns, dvs_driver::ImuVector& out,
                 dvs_driver::ImuVector* biases = nullptr);
  /// Start again at sample 0 (a new run: the biases keep walking from where they are).
  void restart() { next_ = 0; }
  /// The run's time range [s] (idealImu's t_begin, t_end); default unbounded.
  void setTimeRange(double t_begin, double t_end)
  {
    t_begin_ = t_begin;
    t_end_ = t_end;
  }

  const ImuSimParams& params() const { return p_; }
  const Eigen::Vector3d& gyroBias() const { return gyro_bias_; }
  const Eigen::Vector3d& accelBias() const { return accel_bias_; }
  uint64_t nextIndex() const { return next_; }

private:
  ImuSimParams p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Eigen::Vector3d gyro_bias_, accel_bias_;
  uint64_t next_ = 0;
  double t_begin_ = -std::numeric_limits<double>::infinity(), t_end_ = std::numeric_limits<double>::infinity();
};

/// Every sample from 0 to `duration` (inclusive when on the grid), with the biases; the time
/// range is [0, duration].
void simulateImu(const Trajectory& trajectory, double duration, const ImuSimParams& params, uint64_t seed,
                 int64_t offset_ns, dvs_driver::ImuVector& samples, dvs_driver::ImuVector* biases = nullptr);
}  // namespace dvs_screen_sim
