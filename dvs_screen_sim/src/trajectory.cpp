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
  Pose pose;
  pose.p = (1 - s) * p_.start_position + s * p_.end_position;
  pose.q = orientationFromYawPitchRollDeg((1 - s) * p_.start_ypr_deg + s * p_.end_ypr_deg);
  return pose;
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
  Pose pose;
  pose.q = q_cam_world.conjugate().normalized();
  pose.p = -(pose.q * Eigen::Vector3d(0, 0, d));
  return pose;
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
  Pose pose;
  pose.p = Eigen::Vector3d(p_.offset.x() + p_.sway * std::sin(w * t),
                           p_.offset.y() + height + 0.5 * p_.sway * std::sin(1.3 * w * t + 1.0),
                           p_.distance + 0.5 * p_.sway * std::sin(0.7 * w * t + 2.0));
  pose.q = (lookingAtWallOrientation() * axisAngle(rollAt(t), Eigen::Vector3d::UnitZ())).normalized();
  return pose;
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
  Pose pose;
  pose.p = Eigen::Vector3d(v[0], v[1], p_.distance + v[2]);
  pose.q = orientationFromYawPitchRollDeg(Eigen::Vector3d(v[3], v[4], v[5]) / kDegToRad);
  return pose;
}

// ---------------------------------------------------------------- sampled (file playback)
SampledTrajectory::SampledTrajectory(PoseTrajectory poses) : poses_(std::move(poses))
{
  if (poses_.size() < 2)
    throw TrajectoryError("a sampled trajectory needs at least 2 poses (got " + std::to_string(poses_.size()) + ")");
  const double t0 = poses_.front().t;
  for (size_t i = 0; i < poses_.size(); ++i)
  {
    poses_[i].t -= t0;
    if (i > 0 && !(poses_[i].t > poses_[i - 1].t))
      throw TrajectoryError("sampled trajectory times must strictly increase (pose " + std::to_string(i) + ")");
    poses_[i].T_world_cam.q.normalize();
    if (i > 0 && poses_[i].T_world_cam.q.dot(poses_[i - 1].T_world_cam.q) < 0)
      poses_[i].T_world_cam.q.coeffs() *= -1;  // same hemisphere for SQUAD
  }
  const size_t n = poses_.size();
  squad_s_.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Quaterniond& qi = poses_[i].T_world_cam.q;
    if (i == 0 || i + 1 == n)
    {
      squad_s_[i] = qi;
      continue;
    }
    const Eigen::Quaterniond qinv = qi.conjugate();
    const Eigen::Vector3d l =
        quatLog(qinv * poses_[i + 1].T_world_cam.q) + quatLog(qinv * poses_[i - 1].T_world_cam.q);
    squad_s_[i] = (qi * quatExp(-0.25 * l)).normalized();
  }
}

Pose SampledTrajectory::poseAt(double t) const
{
  if (t <= poses_.front().t)
    return poses_.front().T_world_cam;
  if (t >= poses_.back().t)
    return poses_.back().T_world_cam;
  const auto it = std::upper_bound(poses_.begin(), poses_.end(), t,
                                   [](double tt, const StampedPose& sp) { return tt < sp.t; });
  const size_t i1 = static_cast<size_t>(it - poses_.begin());
  const size_t i0 = i1 - 1;
  const size_t n = poses_.size();
  const double t0 = poses_[i0].t, t1 = poses_[i1].t, h = t1 - t0;
  const double s = (t - t0) / h;
  const Eigen::Vector3d& p0 = poses_[i0].T_world_cam.p;
  const Eigen::Vector3d& p1 = poses_[i1].T_world_cam.p;
  auto tangent = [&](size_t i) -> Eigen::Vector3d {
    const size_t a = i == 0 ? 0 : i - 1;
    const size_t b = i + 1 == n ? i : i + 1;
    return (poses_[b].T_world_cam.p - poses_[a].T_world_cam.p) / (poses_[b].t - poses_[a].t);
  };
  const Eigen::Vector3d m0 = tangent(i0) * h, m1 = tangent(i1) * h;
  const double s2 = s * s, s3 = s2 * s;
  Pose pose;
  pose.p = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
  const Eigen::Quaterniond a = poses_[i0].T_world_cam.q.slerp(s, poses_[i1].T_world_cam.q);
  const Eigen::Quaterniond b = squad_s_[i0].slerp(s, squad_s_[i1]);
  pose.q = a.slerp(2 * s * (1 - s), b).normalized();
  return pose;
}

PoseTrajectory sampleTrajectory(const Trajectory& trajectory, double duration, double rate_hz)
{
  if (!(rate_hz > 0))
    throw TrajectoryError("ground-truth rate must be > 0");
  PoseTrajectory out;
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
