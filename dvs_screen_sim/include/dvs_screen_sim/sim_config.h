#pragma once
// The simulator's complete configuration: scenario defaults, overridden by a YAML file, resolved
// into typed structures (camera, scene, trajectory, event model, sampling) plus the resolved
// YAML tree that is written next to the outputs (config.yaml). Every key is documented in the
// package README; unknown keys are errors (a typo must not be silently ignored).
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/param_table.h>
#include <dvs_screen_sim/event_simulator.h>
#include <dvs_screen_sim/imu_simulator.h>
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/trajectory.h>
#include <yaml-cpp/yaml.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace dvs_screen_sim
{
class ConfigError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

/// Scenario names: flip, helix, circle, linear, random, file.
const std::vector<std::string>& scenarioNames();

struct SimConfig
{
  std::string scenario = "flip";
  uint64_t seed = 0;
  double duration = 0;            ///< simulated length [s] (resolved, > 0)
  int64_t time_offset_ns = 0;     ///< added to every output time stamp
  double groundtruth_rate = 1000; ///< [Hz]
  double packet_period = 1e-3;    ///< [s] of bag / ROS event packets
  dvs_calibration::CameraModel camera;
  Scene scene;
  EventModelConfig events;
  SamplingConfig sampling;
  ImuSimParams imu;     ///< the camera's IMU (the `imu` section)
  YAML::Node resolved;  ///< the full resolved configuration tree (what config.yaml holds)
};

/// The run parameters at the configuration's top level (YAML keys of these names). The live
/// simulator node takes `duration` and `packet_period` as ROS parameters of the same names: the
/// same table entries (bounds, units, documentation) serve both paths.
struct SimRunParams
{
  double duration = 0.0;            ///< [s], 0: the scenario's natural length
  double time_offset = 0.0;         ///< [s] added to every output time stamp
  double groundtruth_rate = 1000.0; ///< [Hz]
  double packet_period = 1e-3;      ///< [s]
};
/// Adds `duration` and `packet_period` (the names the ROS node shares) to `table`.
void addSharedRunParams(dvs_driver::ParamTable& table, SimRunParams& p);
/// The top level's four run parameters (what resolveSimConfig validates them with).
dvs_driver::ParamTable simRunParamTable(SimRunParams& p);

/// The scenario's default configuration tree (every key, with comments lost).
YAML::Node defaultConfigTree(const std::string& scenario);

/// Resolve: defaults of `scenario`, deep-merged with `overrides` (may be null), then `seed` and
/// `duration` when given. Throws ConfigError naming the parameter for unknown keys, wrong types
/// or invalid values (also wrapping camera, scene and trajectory errors).
SimConfig resolveSimConfig(const std::string& scenario, const YAML::Node& overrides,
                           std::optional<uint64_t> seed = std::nullopt,
                           std::optional<double> duration = std::nullopt);
/// Same, reading the overrides from a YAML file (empty path: none).
SimConfig resolveSimConfigFile(const std::string& scenario, const std::string& config_path,
                               std::optional<uint64_t> seed = std::nullopt,
                               std::optional<double> duration = std::nullopt);

/// The trajectory the configuration describes.
std::unique_ptr<Trajectory> makeTrajectory(const SimConfig& config);
}  // namespace dvs_screen_sim
