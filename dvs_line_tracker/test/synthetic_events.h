#pragma once
// Test support: a small exact event generator for unit tests (not a DVS model: the suite's software
// DVS lives in dvs_screen_sim). The map's polygons are dark on a bright background; a pixel
// fires one event each time its centre crosses a projected polygon edge (OFF entering the
// polygon, ON leaving it), at the crossing time interpolated between fine time steps. Uniform
// background noise can be added. Ideal pinhole camera (no distortion), convex polygons in front
// of the camera.
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/event.h>
#include <dvs_line_tracker/pose_types.h>
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/pose_initializer.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace dvs_line_tracker
{
/// T_world_camera as a function of time (s).
using PoseFunction = std::function<Pose(double t_s)>;

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
  Pose pose;
};

struct SyntheticSequence
{
  dvs_driver::EventVector events;
  std::vector<GroundTruthSample> ground_truth;  ///< at 1 kHz
};

SyntheticSequence generateSyntheticEvents(const LineMap& map, const PoseFunction& trajectory,
                                          const SyntheticEventParams& params);

/// lookAt: the suite's one (dvs_calibration/pose.h).
using dvs_calibration::lookAt;

/// The generator's camera as a camera model: 128x128, f = 115 px, centred, no distortion.
inline dvs_calibration::CameraModel idealCamera()
{
  dvs_calibration::CameraIntrinsics in;
  in.width = in.height = 128;
  in.fx = in.fy = 115;
  in.cx = in.cy = 63.5;
  return dvs_calibration::CameraModel(in);
}
}  // namespace dvs_line_tracker
