#pragma once
// The scene space of the start-anywhere sweep (benchmark_init_sweep and the end-to-end tests):
// a scene is a sensor, a lens (field of view, radial distortion), a target distance given as the
// fraction of the image height a polygon covers, a motion (slow orbit, hand-held, 2000 deg/s
// flip), a map (square, two squares, square + triangle, square seen at 60 deg), a noise class
// (realistic, heavy, low contrast) and whether part of the map starts outside the image. Every
// scene is simulated by the suite's software DVS (dvs_screen_sim) from a seed.
#include <dvs_calibration/camera_model.h>
#include <dvs_line_tracker/line_map.h>
#include <dvs_screen_sim/event_simulator.h>
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/trajectory.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dvs_line_tracker
{
enum class SweepMotion
{
  kSlow,      ///< 0.1 m/s orbit, roll swaying at 15 deg/s peak
  kHandheld,  ///< 0.4 m/s orbit, 60 deg/s roll sway
  kFlip,      ///< slow hover, then a full roll at 2000 deg/s peak rising by a quarter of the distance
};
enum class SweepMap
{
  kSquare,
  kTwoSquares,
  kSquareTriangle,
  kSteepSquare,  ///< one square seen 60 deg off its normal
};
enum class SweepNoise
{
  kRealistic,    ///< 0.2 Hz/px background, 0.1 ms latency jitter, sigma_C 0.03
  kHeavy,        ///< 2 Hz/px background, 1 ms time-stamp jitter, sigma_C 0.06 (20 % of C)
  kLowContrast,  ///< grey (0.3) on white (0.9): contrast ratio 3; 0.5 Hz/px background
};

struct SweepSceneSpec
{
  int width = 128, height = 128;
  double hfov_deg = 58;   ///< horizontal field of view of the (distorted) image
  double k1 = 0;          ///< radial distortion (k2 chosen to keep the lens one-to-one)
  double coverage = 0.5;  ///< polygon height / image height at the start
  SweepMotion motion = SweepMotion::kSlow;
  SweepMap map = SweepMap::kSquare;
  SweepNoise noise = SweepNoise::kRealistic;
  bool partial = false;   ///< a corner, or part of one side, starts outside the image
  double flip_repeat_s = 0;  ///< flip motion: > 0, the flip repeats every this many seconds
  uint64_t seed = 1;
};

struct SweepScene
{
  SweepSceneSpec spec;
  dvs_calibration::CameraModel camera;
  dvs_screen_sim::Scene scene;
  LineMap map;
  std::shared_ptr<dvs_screen_sim::Trajectory> trajectory;
  dvs_screen_sim::EventModelConfig events;
  double duration = 1.5;  ///< [s]
  double distance = 1;    ///< camera to target at the start [m]
  double polygon_side = 0.9;  ///< [m]
  double coverage = 0.5;      ///< polygon side / image height at the start (below the spec's for two polygons that must fit side by side)
  Eigen::Vector3d target{0, 0, 0};  ///< the map's centre (world)
};

/// Builds the scene (throws std::invalid_argument for an impossible specification).
SweepScene buildSweepScene(const SweepSceneSpec& spec);

/// The sweep's scenes: `count` specifications covering the space (every sensor with every lens
/// class, distance class, motion, map and noise class in rotation), seeded by their index.
std::vector<SweepSceneSpec> sweepSceneSpecs(int count);

/// Short labels for the table.
std::string sensorLabel(const SweepSceneSpec& s);
std::string lensLabel(const SweepSceneSpec& s);
const char* motionLabel(SweepMotion m);
const char* mapLabel(SweepMap m);
const char* noiseLabel(SweepNoise n);
}  // namespace dvs_line_tracker
