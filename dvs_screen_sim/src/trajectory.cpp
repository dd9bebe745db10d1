#include <dvs_screen_sim/trajectory.h>

#include <algorithm>
#include <cmath>

namespace dvs_screen_sim
{
namespace
{
constexpr double kDegToRad = M_PI / 180.0;

Eigen::Quaterniond axisAngle(double angle, const Eigen::Vector3d& axis)
{
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis));
}

Eigen::Vector3d quatLog(const Eigen::Quaterniond& q)
{
  const Eigen::Vector3d v = q.vec();
  const double n = v.norm();
  if (n < 1e-12)
    return Eigen::Vector3d::Zero();
  return v / n * std::atan2(n, q.w());
}

Eigen::Quaterniond quatExp(const Eigen::Vector3d& v)
{
  const double th = v.norm();
  if (th < 1e-12)
    return Eigen::Quaterniond::Identity();
  const Eigen::Vector3d a = v / th * std::sin(th);
  return Eigen::Quaterniond(std::cos(th), a.x(), a.y(), a.z());
}

double normalCdf(double u)
{
  return 0.5 * std::erfc(-u / std::sqrt(2.0));
}
}  // namespace

Eigen::Quaterniond orientationFromYawPitchRollDeg(const Eigen::Vector3d& ypr_deg)
{
  return (lookingAtWallOrientation() * axisAngle(ypr_deg.x() * kDegToRad, Eigen::Vector3d::UnitY()) *
          axisAngle(ypr_deg.y() * kDegToRad, Eigen::Vector3d::UnitX()) *
          axisAngle(ypr_deg.z() * kDegToRad, Eigen::Vector3d::UnitZ()))
      .normalized();
}

// ---------------------------------------------------------------- linear
LinearTrajectory::LinearTrajectory(const LinearTrajectoryParams& params) : p_(params)
{
  if (!(p_.duration > 0))
    throw TrajectoryError("trajectory.linear.duration must be > 0");
}

Pose LinearTrajectory::poseAt(double t) const
{
  const double s = std::clamp(t / p_.duration, 0.0, 1.0);
  return Pose::fromWorldCamera(orientationFromYawPitchRollDeg((1 - s) * p_.start_ypr_deg + s * p_.end_ypr_deg),
                               Eigen::Vector3d((1 - s) * p_.start_position + s * p_.end_position));
}

// ---------------------------------------------------------------- helix (Eq. 4.5)
HelixTrajectory::HelixTrajectory(const HelixTrajectoryParams& params) : p_(params)
{
  if (!(p_.duration > 0))
    throw TrajectoryError("trajectory helix/circle duration must be > 0");
  if (!(p_.start_distance > 0) || !(p_.end_distance > 0))
    throw TrajectoryError("trajectory helix/circle distances must be > 0");
  if (!(std::abs(p_.tilt_deg) < 89))
    throw TrajectoryError("trajectory helix/circle tilt_deg must be within (-89, 89)");
}

Pose HelixTrajectory::poseAt(double t) const
{
  const double s = t / p_.duration;
  const double theta = 2 * M_PI * p_.turns * s;
  const double phi = M_PI + p_.tilt_deg * kDegToRad;
  const double sc = std::clamp(s, 0.0, 1.0);
  const double d = p_.start_distance + (p_.end_distance - p_.start_distance) * sc;
  const Eigen::Quaterniond q_cam_world =
      axisAngle(phi, Eigen::Vector3d::UnitX()) * axisAngle(theta, Eigen::Vector3d::UnitZ());
  const Eigen::Quaterniond q_world_camera = q_cam_world.conjugate().normalized();
  return Pose::fromWorldCamera(q_world_camera, Eigen::Vector3d(-(q_world_camera * Eigen::Vector3d(0, 0, d))));
}

// ---------------------------------------------------------------- flip
FlipTrajectory::FlipTrajectory(const FlipTrajectoryParams& params) : p_(params)
{
  if (!(p_.distance > 0))
    throw TrajectoryError("trajectory.flip.distance must be > 0");
  if (!(p_.peak_rate_deg_s > 0))
    throw TrajectoryError("trajectory.flip.peak_rate_deg_s must be > 0");
  if (p_.flips < 0)
    throw TrajectoryError("trajectory.flip.flips must be >= 0");
  if (!(p_.flip_interval > 0))
    throw TrajectoryError("trajectory.flip.flip_interval must be > 0");
  // A Gaussian rate profile of peak w integrates to w * sigma * sqrt(2 pi) = one full turn.
  sigma_roll_ = std::sqrt(2 * M_PI) / (p_.peak_rate_deg_s * kDegToRad);
  sigma_height_ = 2.5 * sigma_roll_;
}

double FlipTrajectory::naturalDuration() const
{
  return 2 * p_.first_flip_time + std::max(0, p_.flips - 1) * p_.flip_interval;
}

double FlipTrajectory::rollAt(double t) const
{
  double roll = 0;
  for (int i = 0; i < p_.flips; ++i)
    roll += 2 * M_PI * normalCdf((t - p_.first_flip_time - i * p_.flip_interval) / sigma_roll_);
  return roll;
}

double FlipTrajectory::rollRateAt(double t) const
{
  double rate = 0;
  for (int i = 0; i < p_.flips; ++i)
  {
    const double u = (t - p_.first_flip_time - i * p_.flip_interval) / sigma_roll_;
    rate += p_.peak_rate_deg_s * kDegToRad * std::exp(-0.5 * u * u);
  }
  return rate;
}

Pose FlipTrajectory::poseAt(double t) const
{
  double height = 0;
  for (int i = 0; i < p_.flips; ++i)
  {
    const double u = (t - p_.first_flip_time - i * p_.flip_interval) / sigma_height_;
    height += p_.rise * std::exp(-0.5 * u * u);
  }
  const double w = 2 * M_PI * p_.sway_frequency;
  const Eigen::Vector3d p(p_.offset.x() + p_.sway * std::sin(w * t),
                          p_.offset.y() + height + 0.5 * p_.sway * std::sin(1.3 * w * t + 1.0),
                          p_.distance + 0.5 * p_.sway * std::sin(0.7 * w * t + 2.0));
  return Pose::fromWorldCamera(
      (lookingAtWallOrientation() * axisAngle(rollAt(t), Eigen::Vector3d::UnitZ())).normalized(), p);
}

// ---------------------------------------------------------------- random
RandomTrajectory::RandomTrajectory(const RandomTrajectoryParams& params, uint64_t seed) : p_(params)
{
  if (!(p_.distance > 0))
    throw TrajectoryError("trajectory.random.distance must be > 0");
  if (!(p_.min_frequency > 0) || !(p_.max_frequency >= p_.min_frequency))
    throw TrajectoryError("trajectory.random: need 0 < min_frequency <= max_frequency");
  if (p_.components < 1)
    throw TrajectoryError("trajectory.random.components must be >= 1");
  std::mt19937_64 rng(seed ^ 0x5eed7a11ULL);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int a = 0; a < 6; ++a)
  {
    const double amplitude = a < 3 ? p_.position_amplitude[a] : p_.ypr_amplitude_deg[a - 3] * kDegToRad;
    std::vector<double> weights(p_.components);
    double sum = 0;
    for (auto& wgt : weights)
      sum += (wgt = 0.2 + uni(rng));
    for (int c = 0; c < p_.components; ++c)
    {
      const double f = p_.min_frequency + (p_.max_frequency - p_.min_frequency) * uni(rng);
      axes_[a].push_back({amplitude * weights[c] / sum, 2 * M_PI * f, 2 * M_PI * uni(rng)});
    }
  }
}

Pose RandomTrajectory::poseAt(double t) const
{
  double v[6];
  for (int a = 0; a < 6; ++a)
  {
    // Subtract the value at t = 0 so that the motion starts at the nominal pose.
    v[a] = 0;
    for (const auto& s : axes_[a])
      v[a] += s.amplitude * (std::sin(s.omega * t + s.phase) - std::sin(s.phase));
  }
  return Pose::fromWorldCamera(orientationFromYawPitchRollDeg(Eigen::Vector3d(v[3], v[4], v[5]) / kDegToRad),
                               Eigen::Vector3d(v[0], v[1], p_.distance + v[2]));
}

// ---------------------------------------------------------------- sampled (file playback)
SampledTrajectory::SampledTrajectory(dvs_calibration::Trajectory poses)
{
  if (poses.size() < 2)
    throw TrajectoryError("a sampled trajectory needs at least 2 poses (got " + std::to_string(poses.size()) + ")");
  const double t0 = poses.front().t;
  const size_t n = poses.size();
  t_.resize(n);
  p_.resize(n);
  q_.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    t_[i] = poses[i].t - t0;
    if (i > 0 && !(t_[i] > t_[i - 1]))
      throw TrajectoryError("sampled trajectory times must strictly increase (pose " + std::to_string(i) + ")");
    p_[i] = poses[i].T_world_camera.p_world_camera();
    q_[i] = poses[i].T_world_camera.q_world_camera();
    if (i > 0 && q_[i].dot(q_[i - 1]) < 0)
      q_[i].coeffs() *= -1;  // same hemisphere for SQUAD
  }
  first_ = poses.front().T_world_camera;
  last_ = poses.back().T_world_camera;
  squad_s_.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Quaterniond& qi = q_[i];
    if (i == 0 || i + 1 == n)
    {
      squad_s_[i] = qi;
      continue;
    }
    const Eigen::Quaterniond qinv = qi.conjugate();
    const Eigen::Vector3d l = quatLog(qinv * q_[i + 1]) + quatLog(qinv * q_[i - 1]);
    squad_s_[i] = (qi * quatExp(-0.25 * l)).normalized();
  }
}

Pose SampledTrajectory::poseAt(double t) const
{
  if (t <= t_.front())
    return first_;
  if (t >= t_.back())
    return last_;
  const auto it = std::upper_bound(t_.begin(), t_.end(), t);
  const size_t i1 = static_cast<size_t>(it - t_.begin());
  const size_t i0 = i1 - 1;
  const size_t n = t_.size();
  const double t0 = t_[i0], t1 = t_[i1], h = t1 - t0;
  const double s = (t - t0) / h;
  const Eigen::Vector3d& p0 = p_[i0];
  const Eigen::Vector3d& p1 = p_[i1];
  auto tangent = [&](size_t i) -> Eigen::Vector3d {
    const size_t a = i == 0 ? 0 : i - 1;
    const size_t b = i + 1 == n ? i : i + 1;
    return (p_[b] - p_[a]) / (t_[b] - t_[a]);
  };
  const Eigen::Vector3d m0 = tangent(i0) * h, m1 = tangent(i1) * h;
  const double s2 = s * s, s3 = s2 * s;
  const Eigen::Vector3d p =
      (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
  const Eigen::Quaterniond a = q_[i0].slerp(s, q_[i1]);
  const Eigen::Quaterniond b = squad_s_[i0].slerp(s, squad_s_[i1]);
  return Pose::fromWorldCamera(a.slerp(2 * s * (1 - s), b).normalized(), p);
}

dvs_calibration::Trajectory sampleTrajectory(const Trajectory& trajectory, double duration, double rate_hz)
{
  if (!(rate_hz > 0))
    throw TrajectoryError("ground-truth rate must be > 0");
  dvs_calibration::Trajectory out;
  const long n = static_cast<long>(std::floor(duration * rate_hz + 1e-9));
  out.reserve(static_cast<size_t>(n + 1));
  for (long i = 0; i <= n; ++i)
  {
    const double t = static_cast<double>(i) / rate_hz;
    out.push_back({t, trajectory.poseAt(t)});
  }
  return out;
}
}  // namespace dvs_screen_sim
