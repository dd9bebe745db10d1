#include <dvs_screen_sim/imu_simulator.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dvs_screen_sim
{
namespace
{
constexpr double kStep = 1e-4;  // central-difference step [s]

Eigen::Matrix3d R_world_imu(const Pose& T_world_camera, const Eigen::Matrix3d& R_camera_imu)
{
  return T_world_camera.R_world_camera() * R_camera_imu;
}

Eigen::Vector3d p_world_imu(const Pose& T_world_camera, const Eigen::Vector3d& p_camera_imu)
{
  return T_world_camera.toWorld(p_camera_imu);
}

Eigen::Vector3d randomVector(std::mt19937_64& rng, std::normal_distribution<double>& normal, double max_norm)
{
  // Direction uniform on the sphere (normalised Gaussian), magnitude uniform in [0, max_norm].
  Eigen::Vector3d d(normal(rng), normal(rng), normal(rng));
  const double n = d.norm();
  const double magnitude = std::uniform_real_distribution<double>(0.0, max_norm)(rng);
  return n > 0 ? Eigen::Vector3d(d / n * magnitude) : Eigen::Vector3d::Zero();
}

void require(bool ok, const std::string& message)
{
  if (!ok)
    throw std::invalid_argument(message);
}
}  // namespace

double ImuSimParams::gyroSigma() const { return gyro_noise_density * std::sqrt(rate); }
double ImuSimParams::accelSigma() const { return accel_noise_density * std::sqrt(rate); }

dvs_driver::ParamTable imuParamTable(ImuSimParams& p)
{
  dvs_driver::ParamTable t("dvs_screen_sim configuration, imu");
  t.add("rate", p.rate, "Hz", 0, 1e6, "IMU samples per second").min_exclusive = true;
  t.add("gyro_noise_density", p.gyro_noise_density, "rad/s/sqrt(Hz)", 0, 1,
        "gyroscope white noise (per sample: density * sqrt(rate))");
  t.add("gyro_random_walk", p.gyro_random_walk, "rad/s^2/sqrt(Hz)", 0, 1,
        "gyroscope bias random walk (per sample: walk / sqrt(rate))");
  t.add("accel_noise_density", p.accel_noise_density, "m/s^2/sqrt(Hz)", 0, 10,
        "accelerometer white noise (per sample: density * sqrt(rate))");
  t.add("accel_random_walk", p.accel_random_walk, "m/s^3/sqrt(Hz)", 0, 10,
        "accelerometer bias random walk (per sample: walk / sqrt(rate))");
  t.add("initial_gyro_bias_max", p.initial_gyro_bias_max, "rad/s", 0, 10,
        "magnitude bound of the random initial gyroscope bias (when initial_gyro_bias is null)");
  t.add("initial_accel_bias_max", p.initial_accel_bias_max, "m/s^2", 0, 100,
        "magnitude bound of the random initial accelerometer bias (when initial_accel_bias is null)");
  return t;
}

void ImuSimParams::validate() const
{
  ImuSimParams copy = *this;
  const std::string bad = imuParamTable(copy).validate();
  require(bad.empty(), "imu: " + bad);
  require(gravity.allFinite(), "imu.gravity must be finite");
  require(p_camera_imu.allFinite(), "imu.extrinsic_translation must be finite");
  require(q_camera_imu.coeffs().allFinite() && std::abs(q_camera_imu.norm() - 1.0) < 1e-6,
          "imu.extrinsic_rotation must be a unit quaternion [qx, qy, qz, qw]");
  require(!initial_gyro_bias || initial_gyro_bias->allFinite(), "imu.initial_gyro_bias must be finite");
  require(!initial_accel_bias || initial_accel_bias->allFinite(), "imu.initial_accel_bias must be finite");
}

ImuTruth idealImu(const Trajectory& trajectory, double t, const ImuSimParams& params, double t_begin, double t_end)
{
  const Eigen::Matrix3d R_ci = params.q_camera_imu.toRotationMatrix();
  // The stencil's centre: t, moved inside [t_begin + h, t_end - h] at the range's ends.
  double c = t;
  if (t_end - t_begin > 2 * kStep)
    c = std::clamp(t, t_begin + kStep, t_end - kStep);
  const Pose before = trajectory.poseAt(c - kStep), now = trajectory.poseAt(c), after = trajectory.poseAt(c + kStep);
  ImuTruth truth;
  // Body rate: log(R(c-h)^T R(c+h)) / 2h (second order at c).
  const Eigen::Matrix3d R_now = R_world_imu(c == t ? now : trajectory.poseAt(t), R_ci);
  const Eigen::AngleAxisd d(R_world_imu(before, R_ci).transpose() * R_world_imu(after, R_ci));
  truth.gyro = d.axis() * d.angle() / (2 * kStep);
  const Eigen::Vector3d a_world = (p_world_imu(after, params.p_camera_imu) - 2 * p_world_imu(now, params.p_camera_imu) +
                                   p_world_imu(before, params.p_camera_imu)) /
                                  (kStep * kStep);
  truth.accel = R_now.transpose() * (a_world - params.gravity);
  return truth;
}

ImuSimulator::ImuSimulator(const ImuSimParams& params, uint64_t seed) : p_(params), rng_(seed ^ 0x1a0b5eed0f1a4d5bULL)
{
  p_.validate();
  gyro_bias_ = p_.initial_gyro_bias ? *p_.initial_gyro_bias : randomVector(rng_, normal_, p_.initial_gyro_bias_max);
  accel_bias_ = p_.initial_accel_bias ? *p_.initial_accel_bias : randomVector(rng_, normal_, p_.initial_accel_bias_max);
}

void ImuSimulator::advanceTo(const Trajectory& trajectory, double t, int64_t offset_ns, dvs_driver::ImuVector& out,
                             dvs_driver::ImuVector* biases)
{
  const double dt = 1.0 / p_.rate;
  const double sigma_g = p_.gyroSigma(), sigma_a = p_.accelSigma();
  const double walk_g = p_.gyro_random_walk * std::sqrt(dt), walk_a = p_.accel_random_walk * std::sqrt(dt);
  for (;; ++next_)
  {
    const double tk = static_cast<double>(next_) / p_.rate;
    if (tk > t + 1e-12)
      break;
    const ImuTruth truth = idealImu(trajectory, tk, p_, t_begin_, t_end_);
    dvs_driver::ImuSample s;
    s.t_ns = offset_ns + std::llround(static_cast<double>(next_) * 1e9 / p_.rate);
    for (int i = 0; i < 3; ++i)
    {
      s.gyro[i] = truth.gyro[i] + gyro_bias_[i] + (sigma_g > 0 ? sigma_g * normal_(rng_) : 0.0);
      s.accel[i] = truth.accel[i] + accel_bias_[i] + (sigma_a > 0 ? sigma_a * normal_(rng_) : 0.0);
    }
    out.push_back(s);
    if (biases)
    {
      dvs_driver::ImuSample b;
      b.t_ns = s.t_ns;
      for (int i = 0; i < 3; ++i)
      {
        b.gyro[i] = gyro_bias_[i];
        b.accel[i] = accel_bias_[i];
      }
      biases->push_back(b);
    }
    for (int i = 0; i < 3; ++i)
    {
      if (walk_g > 0)
        gyro_bias_[i] += walk_g * normal_(rng_);
      if (walk_a > 0)
        accel_bias_[i] += walk_a * normal_(rng_);
    }
  }
}

void simulateImu(const Trajectory& trajectory, double duration, const ImuSimParams& params, uint64_t seed,
                 int64_t offset_ns, dvs_driver::ImuVector& samples, dvs_driver::ImuVector* biases)
{
  ImuSimulator sim(params, seed);
  sim.setTimeRange(0.0, duration);
  samples.reserve(samples.size() + static_cast<size_t>(duration * params.rate) + 1);
  sim.advanceTo(trajectory, duration, offset_ns, samples, biases);
}
}  // namespace dvs_screen_sim
