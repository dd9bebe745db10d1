#pragma once
// The IMU fusion's evaluation on the software DVS's flips, shared by benchmark_imu_fusion and
// test_imu_fusion: simulate a flip with its IMU, then track it with or without the IMU (its
// samples optionally edited, a blackout of every event optionally cut out) and measure it
// against ground truth: accuracy, the error right after the blackout, the tracker's and the
// IMU's counters, and the covariance consistency of the odometry (with IMU) or of the vision's
// covariance (without).
#include "covariance_consistency.h"

#include <dvs_calibration/trajectory_accuracy.h>
#include <dvs_line_tracker/imu_propagator.h>
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/sim_config.h>

#include <cstdio>
#include <functional>
#include <memory>
#include <string>

namespace dvs_line_tracker
{
struct FlipScene
{
  dvs_screen_sim::SimConfig config;
  dvs_screen_sim::SimulationOutput output;
  std::unique_ptr<dvs_screen_sim::Trajectory> trajectory;
  dvs_calibration::Trajectory ground_truth;
  /// The true camera pose at t_ns (simulation time + the configuration's offset).
  Pose truth(int64_t t_ns) const;
};

/// The flip scenario with YAML `overrides` (e.g. "trajectory: {flip: {distance: 2.3}}").
FlipScene simulateFlip(const std::string& overrides, uint64_t seed);

/// Edits an IMU sample before the tracker gets it; false drops it.
using ImuSampleFilter = std::function<bool(dvs_driver::ImuSample&)>;

struct FlipRunOptions
{
  LineTrackerParams params;
  bool use_imu = false;
  ImuSampleFilter imu_filter;   ///< empty: the samples as simulated
  double blackout_from_s = 0;   ///< simulation time [s]
  double blackout_s = 0;        ///< no event in [from, from + this) (0: none)
  std::FILE* trace = nullptr;   ///< per consistency sample: t, position error (3) and sigmas (3), rotation error (3) and sigmas (3)
};

struct FlipRunResult
{
  dvs_calibration::AccuracyReport all, after;  ///< after: from the blackout's end on
  TrackerStats stats;
  ImuStatus imu_status = ImuStatus::kWaiting;
  std::string imu_message;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  ///< the filter's at the end
  double after_gap_position_m = -1, after_gap_orientation_rad = -1;  ///< first pose after the blackout (-1: not tracking)
  /// The odometry's covariance (plus LineTracker::motionLagCovariance, as ~odometry reports it)
  /// against its errors at every IMU sample (with IMU), or the
  /// tracker's pose against its vision-only covariance (LineTracker::visionOnlyPoseCovariance)
  /// every 1 ms (without).
  CovarianceConsistency consistency;
  bool odometry_positive_definite = true;  ///< every odometry's pose and velocity covariance
};

FlipRunResult runFlip(const FlipScene& scene, const FlipRunOptions& options);
}  // namespace dvs_line_tracker
