#pragma once
// How well a pose covariance describes the pose's error: per axis (position in the world,
// rotation error in camera axes, the tracker's and the odometry's convention), the fraction of
// errors inside 1 and 3 sigma (a consistent Gaussian estimate: 68.3 % and 99.7 %). The one
// consistency measure of the benchmarks (benchmark_imu_fusion, benchmark_init_sweep).
#include <dvs_line_tracker/pose_types.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>

namespace dvs_line_tracker
{
struct CovarianceConsistency
{
  uint64_t samples = 0;
  uint64_t inside1 = 0, inside3 = 0;          ///< position axes (3 per sample)
  uint64_t inside1_rot = 0, inside3_rot = 0;  ///< rotation axes

  /// One sample; `error_position` and `error_rotation` (axis-angle, camera axes) receive the
  /// error when given.
  void add(const Pose& truth, const Pose& estimate, const Matrix6d& covariance,
           Eigen::Vector3d* error_position = nullptr, Eigen::Vector3d* error_rotation = nullptr)
  {
    const Eigen::Vector3d dp = estimate.p_world_camera() - truth.p_world_camera();
    const Eigen::AngleAxisd aa(estimate.R_camera_world * truth.R_world_camera());
    const Eigen::Vector3d dr = aa.angle() * aa.axis();
    for (int a = 0; a < 3; ++a)
    {
      const double sp = std::sqrt(covariance(3 + a, 3 + a)), sr = std::sqrt(covariance(a, a));
      inside1 += std::abs(dp[a]) <= sp;
      inside3 += std::abs(dp[a]) <= 3 * sp;
      inside1_rot += std::abs(dr[a]) <= sr;
      inside3_rot += std::abs(dr[a]) <= 3 * sr;
    }
    ++samples;
    if (error_position)
      *error_position = dp;
    if (error_rotation)
      *error_rotation = dr;
  }
  void add(const CovarianceConsistency& o)
  {
    samples += o.samples;
    inside1 += o.inside1;
    inside3 += o.inside3;
    inside1_rot += o.inside1_rot;
    inside3_rot += o.inside3_rot;
  }
  /// Fractions (0-1) of the axes' errors inside 1 / 3 sigma; 0 without samples.
  double position1() const { return fraction(inside1); }
  double position3() const { return fraction(inside3); }
  double rotation1() const { return fraction(inside1_rot); }
  double rotation3() const { return fraction(inside3_rot); }

private:
  double fraction(uint64_t n) const { return samples ? static_cast<double>(n) / (3.0 * samples) : 0.0; }
};
}  // namespace dvs_line_tracker
