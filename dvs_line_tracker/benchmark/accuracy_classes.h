#pragma once
// The accuracy classes of issue 15 (benchmark_accuracy and the end-to-end accuracy tests share
// them): each is a software-DVS scenario with overrides (sensor, distance, speed, noise, map,
// contrast), simulated from a seed and tracked from its first pose on, scored with the suite's
// one accuracy metric against the simulator's ground truth.
#include <dvs_calibration/trajectory_accuracy.h>
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/imu_propagator.h>
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/sim_config.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dvs_line_tracker
{
struct AccuracyClass
{
  std::string key;        ///< short name for --class (e.g. "flip23")
  std::string name;       ///< the issue's row
  std::string scenario;   ///< the simulator's scenario
  std::string overrides;  ///< YAML deep-merged into its defaults
  std::string before;     ///< the figure the issue reported
  std::string target;     ///< the issue's target
};

/// Every class, in the order, with the two one-square comparisons of the two-square class.
const std::vector<AccuracyClass>& accuracyClasses();
/// The class with that key (throws std::invalid_argument naming the known keys).
const AccuracyClass& accuracyClass(const std::string& key);

struct AccuracyScene
{
  dvs_screen_sim::SimConfig config;
  dvs_screen_sim::SimulationOutput output;
  dvs_calibration::Trajectory ground_truth;
  LineMap map;  ///< every polygon of the simulated scene that is in the map
};

/// The class's simulator configuration for `seed` (throws dvs_screen_sim::ConfigError).
dvs_screen_sim::SimConfig accuracyConfig(const AccuracyClass& c, uint64_t seed);
/// The tracker's map of a simulated scene: every polygon with in_map set.
LineMap mapOfScene(const dvs_screen_sim::Scene& scene, const std::string& name);
/// Configure, simulate, and build the map.
AccuracyScene simulateAccuracyScene(const AccuracyClass& c, uint64_t seed);

/// A simulated IMU fused into a tracker as the nodelet does: an ImuPropagator (params.imu) set
/// as the tracker's propagator, each sample given to it before the first event after it. With
/// no samples (nullptr) it does nothing.
class ImuFeed
{
public:
  ImuFeed(LineTracker& tracker, const LineTrackerParams& params, const dvs_driver::ImuVector* samples);
  /// Give the samples up to (and at) t_ns; call before processEvent of an event at t_ns.
  void before(int64_t t_ns)
  {
    for (; imu_ && next_ < samples_->size() && (*samples_)[next_].t_ns <= t_ns; ++next_)
      imu_->addSample((*samples_)[next_]);
  }
  /// The propagator (nullptr without samples).
  const ImuPropagator* propagator() const { return imu_.get(); }

private:
  const dvs_driver::ImuVector* samples_;
  std::shared_ptr<ImuPropagator> imu_;
  size_t next_ = 0;
};

struct AccuracyRun
{
  dvs_calibration::AccuracyReport accuracy;
  TrackerStats stats;
  uint64_t events = 0;
  double tracker_cpu_s = 0;  ///< thread CPU time of the event loop over the whole run
  std::string imu_status;    ///< with the IMU: its status at the end (imu_propagator.h), else empty
};

/// Tracks every event of the scene; the pose in force after each update is the estimate.
/// `use_imu`: the simulated IMU's samples fused (ImuPropagator with params.imu), each given to
/// the tracker before the first event after it, as the nodelet does; the run's IMU status at the
/// end goes to AccuracyRun::imu_status.
AccuracyRun runAccuracyScene(const AccuracyScene& scene, const LineTrackerParams& params,
                             dvs_calibration::Trajectory* estimates = nullptr, bool use_imu = false);

/// Wall-clock time [s] of every processEvent call that updated the pose, after the first pose
/// (the per-event processing latency while tracking).
/// `imu`: the simulated IMU fused (ImuFeed).
std::vector<double> poseUpdateLatencies(const dvs_calibration::CameraModel& camera, const LineMap& map,
                                        const LineTrackerParams& params, const dvs_driver::EventVector& events,
                                        const dvs_driver::ImuVector* imu = nullptr);
}  // namespace dvs_line_tracker
