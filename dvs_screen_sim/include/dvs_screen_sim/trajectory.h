#pragma once
// Camera trajectories: continuous functions t [s] -> T_world_camera (the suite's Pose). Their
// samples are the suite's stamped trajectory (dvs_calibration::Trajectory, a vector of
// StampedPose); `Trajectory` in this namespace is the continuous function.
//
// World frame of the suite's simulated scenes (wall_pose.h): the wall is the plane z = 0, world
// x points right and world y up on the wall, z out of the wall towards the camera. A camera
// "looking at the wall" sits at z > 0 with R_world_camera = diag(1, -1, -1).
#include <dvs_screen_sim/wall_pose.h>

#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace dvs_screen_sim
{
class TrajectoryError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

class Trajectory
{
public:
  virtual ~Trajectory() = default;
  /// The pose at time t [s]. Defined for every t (trajectories hold or extrapolate smoothly).
  virtual Pose poseAt(double t) const = 0;
  /// The length the trajectory was designed for [s] (0 when it has none).
  virtual double naturalDuration() const { return 0.0; }
};

/// A camera that does not move.
class StaticTrajectory : public Trajectory
{
public:
  explicit StaticTrajectory(const Pose& T_world_camera) : pose_(T_world_camera) {}
  Pose poseAt(double) const override { return pose_; }

private:
  Pose pose_;
};

/// Camera orientation from yaw/pitch/roll in degrees, relative to looking at the wall:
/// R_world_camera = R_look * Ry(yaw) * Rx(pitch) * Rz(roll), all about CAMERA axes (yaw about the
/// image's vertical axis y, pitch about x, roll about the optical axis z).
Eigen::Quaterniond orientationFromYawPitchRollDeg(const Eigen::Vector3d& ypr_deg);

/// The thesis's linear trajectory (ch. 3): translation and yaw/pitch/roll interpolated
/// linearly from start to end over `duration`; holds the end pose afterwards.
struct LinearTrajectoryParams
{
  Eigen::Vector3d start_position{-0.3, -0.2, 1.3};
  Eigen::Vector3d start_ypr_deg{10, -5, -10};
  Eigen::Vector3d end_position{0.3, 0.2, 1.8};
  Eigen::Vector3d end_ypr_deg{-10, 5, 20};
  double duration = 2.0;
};
class LinearTrajectory : public Trajectory
{
public:
  explicit LinearTrajectory(const LinearTrajectoryParams& params);
  Pose poseAt(double t) const override;
  double naturalDuration() const override { return p_.duration; }

private:
  LinearTrajectoryParams p_;
};

/// The thesis's conic helix (Eq. 4.5): view matrix M = [Rx(phi) Rz(theta) | (0, 0, d)] with
/// theta = 360 deg * turns * t / T, phi = 180 deg + tilt, d growing linearly from
/// start_distance to end_distance. The optical axis always passes through the wall origin (the
/// square's centre). With start_distance == end_distance it is the thesis's fixed-distance
/// circle.
struct HelixTrajectoryParams
{
  double start_distance = 1.0;  ///< [m]
  double end_distance = 2.5;    ///< [m]
  double tilt_deg = 30.0;       ///< angle between optical axis and wall normal
  double turns = 2.0;
  double duration = 4.0;        ///< T [s]
};
class HelixTrajectory : public Trajectory
{
public:
  explicit HelixTrajectory(const HelixTrajectoryParams& params);
  Pose poseAt(double t) const override;
  double naturalDuration() const override { return p_.duration; }

private:
  HelixTrajectoryParams p_;
};

/// A quadrotor doing flips: hovering in front of the wall (looking at it, small sway), it rolls
/// a full turn about the optical axis with a bell-shaped (Gaussian) roll rate of peak
/// `peak_rate_deg_s`, rising by `rise` metres into the flip and falling back after it.
struct FlipTrajectoryParams
{
  double distance = 2.0;             ///< camera to wall [m]
  Eigen::Vector2d offset{0.0, 0.0};  ///< hover position in the wall plane (x, y) [m]
  double peak_rate_deg_s = 1200.0;   ///< peak roll rate
  double rise = 0.5;                 ///< height gained at the flip's apex [m]
  int flips = 1;
  double first_flip_time = 0.75;     ///< centre of the first flip [s]
  double flip_interval = 1.5;        ///< between flip centres [s]
  double sway = 0.02;                ///< hover sway amplitude [m] (0: still hover)
  double sway_frequency = 0.8;       ///< [Hz]
};
class FlipTrajectory : public Trajectory
{
public:
  explicit FlipTrajectory(const FlipTrajectoryParams& params);
  Pose poseAt(double t) const override;
  double naturalDuration() const override;
  /// Roll angle about the optical axis [rad] and its rate [rad/s] at t.
  double rollAt(double t) const;
  double rollRateAt(double t) const;

private:
  FlipTrajectoryParams p_;
  double sigma_roll_;    ///< std-dev of the Gaussian rate profile [s]
  double sigma_height_;  ///< std-dev of the height bell [s]
};

/// Smooth random 6-DoF motion around a camera looking at the wall centre: each of x, y, z,
/// yaw, pitch, roll is a sum of `components` sinusoids with random frequencies in
/// [min_frequency, max_frequency], random phases and amplitudes summing to the axis amplitude.
struct RandomTrajectoryParams
{
  double distance = 1.5;                             ///< mean distance to the wall [m]
  Eigen::Vector3d position_amplitude{0.2, 0.2, 0.2};  ///< [m]
  Eigen::Vector3d ypr_amplitude_deg{10, 10, 30};
  double min_frequency = 0.2;  ///< [Hz]
  double max_frequency = 1.0;  ///< [Hz]
  int components = 3;
};
class RandomTrajectory : public Trajectory
{
public:
  RandomTrajectory(const RandomTrajectoryParams& params, uint64_t seed);
  Pose poseAt(double t) const override;

private:
  struct Sine
  {
    double amplitude, omega, phase;
  };
  RandomTrajectoryParams p_;
  std::vector<Sine> axes_[6];
};

/// Playback of sampled poses (e.g. from readTumTrajectory): positions by Catmull-Rom cubic
/// interpolation, orientations by SQUAD (both C1 smooth), clamped at the ends. Times are
/// shifted so that the first pose is at t = 0.
class SampledTrajectory : public Trajectory
{
public:
  /// Throws TrajectoryError for fewer than 2 poses or non-increasing times.
  explicit SampledTrajectory(dvs_calibration::Trajectory poses);
  Pose poseAt(double t) const override;
  double naturalDuration() const override { return t_.back(); }

private:
  // The samples as times (shifted to start at 0), positions and orientations (q_world_camera,
  // each in the hemisphere of its predecessor), and the SQUAD control points.
  std::vector<double> t_;
  std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>> p_;
  std::vector<Eigen::Quaterniond, Eigen::aligned_allocator<Eigen::Quaterniond>> q_, squad_s_;
  Pose first_, last_;
};

/// Sample a trajectory at `rate_hz` from 0 to duration (inclusive when it falls on the grid).
dvs_calibration::Trajectory sampleTrajectory(const Trajectory& trajectory, double duration, double rate_hz);
}  // namespace dvs_screen_sim
