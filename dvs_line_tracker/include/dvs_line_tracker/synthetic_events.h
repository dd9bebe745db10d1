#pragma once
// A small exact event generator for tests and benchmarks (not a DVS model: the suite's software
// DVS lives in dvs_screen_sim). The map's polygons are dark on a bright background; a pixel
// fires one event each time its centre crosses a projected polygon edge (OFF entering the
// polygon, ON leaving it), at the crossing time interpolated between fine time steps. Uniform
// background noise can be added. Ideal pinhole camera (no distortion), convex polygons in front
// of the camera.
#include <dvs_driver/event.h>
#include <dvs_line_tracker/camera_pose.h>
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/pose_initializer.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace dvs_line_tracker
{
/// T_world_cam as a function of time (s), returned as the tracker's CameraPose.
using Trajectory = std::function<CameraPose(double t_s)>;

struct SyntheticEventParams
{
  int width = 128, height = 128;
  PinholeK k;                 ///< ideal pinhole camera
  double duration_s = 1.0;
  double time_step_s = 20e-6; ///< pose sampling step (crossing times interpolated inside)
  double noise_rate_hz_per_px = 0.0;
  /// Events per edge crossing (a real DVS fires several: log contrast / threshold), spread
  /// over +-0.25 of the time step around the crossing.
  int events_per_crossing = 1;
  uint64_t seed = 1;
  /// Occlusion: events of map segment `occluded_segment` (nearest-segment test) are dropped in
  /// [occlusion_start_s, occlusion_end_s). -1 = none.
  int occluded_segment = -1;
  double occlusion_start_s = 0, occlusion_end_s = 0;
};

struct GroundTruthSample
{
  double t_s;
  CameraPose pose;
};

struct SyntheticSequence
{
  dvs_driver::EventVector events;
  std::vector<GroundTruthSample> ground_truth;  ///< at 1 kHz
};

SyntheticSequence generateSyntheticEvents(const LineMap& map, const Trajectory& trajectory,
                                          const SyntheticEventParams& params);

/// Camera at `p_world` looking at `target_world`, image "up" (-y) towards `up_world`, rolled
/// by `roll_rad` about the optical axis.
CameraPose lookAt(const Eigen::Vector3d& p_world, const Eigen::Vector3d& target_world, const Eigen::Vector3d& up_world,
                  double roll_rad = 0.0);

/// A drone-like flip in front of the default square (plane z = 0, camera on +z): a short
/// hover drifting sideways, then a full roll about the optical axis with a raised-cosine rate
/// profile peaking at `peak_rate_deg_s`, rising and falling by `rise_m` meanwhile, then hover.
Trajectory flipTrajectory(double distance_m = 1.6, double peak_rate_deg_s = 1200.0, double rise_m = 0.2,
                          double hover_s = 0.15);
/// Duration of flipTrajectory's motion (hover, flip, hover).
double flipDuration(double peak_rate_deg_s = 1200.0, double hover_s = 0.15);
/// A circle in a plane parallel to the wall at `distance_m`, radius distance*tan(tilt),
/// always looking at the square's centre and turning with the orbit (the thesis's view matrix,
/// Eq. 4.5, at a fixed distance): the image of the square rotates once per `period_s`.
Trajectory circleTrajectory(double distance_m = 2.5, double tilt_deg = 15.0, double period_s = 2.0);
}  // namespace dvs_line_tracker
