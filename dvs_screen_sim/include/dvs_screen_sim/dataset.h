#pragma once
// Running a whole simulation offline and writing its dataset folder:
//   events.txt       t x y p (Event Camera Dataset layout, sorted)
//   groundtruth.txt  t px py pz qx qy qz qw (T_world_camera at groundtruth_rate, same time base)
//   calib.txt        fx fy cx cy k1 k2 p1 p2 k3
//   camera_info.yaml the same camera as ROS camera_info YAML
//   map.yaml         the tracker's line map (every edge of every in-map polygon, with `up`)
//   config.yaml      the full resolved configuration (re-running with it reproduces the data)
//   imu.txt          t ax ay az gx gy gz (Event Camera Dataset layout; the IMU's axes, imu_simulator.h)
//   imu_bias_groundtruth.txt  t bax bay baz bgx bgy bgz: the true biases in each imu.txt sample
// Times: simulation time t (starting at 0) + time_offset (default 0), in seconds.
#include <dvs_driver/event.h>
#include <dvs_screen_sim/event_simulator.h>
#include <dvs_screen_sim/wall_pose.h>
#include <dvs_screen_sim/sim_config.h>

#include <fstream>
#include <functional>
#include <memory>
#include <string>

namespace dvs_driver
{
class CheckedFileWriter;
}

namespace dvs_screen_sim
{
struct SimulationOutput
{
  dvs_driver::EventVector events;  ///< all events (empty when they were streamed to a sink)
  uint64_t event_count = 0;
  dvs_calibration::Trajectory groundtruth;      ///< times include the offset
  dvs_driver::ImuVector imu;       ///< IMU samples at config.imu.rate (stamps include the offset)
  dvs_driver::ImuVector imu_bias;  ///< the true biases of each IMU sample (accel, gyro), same stamps
  SimulationStats stats;
  double cpu_seconds = 0;          ///< process CPU time spent in the event simulation
};

/// Receives the events of a simulation chunk by chunk, in time order.
using EventChunkSink = std::function<void(const dvs_driver::EventVector& chunk)>;

/// Simulate config.duration seconds of config.scenario. Without a sink the events are returned
/// in output.events; with one they are streamed to it in chunks of ~0.1 s whose boundaries are
/// multiples of config.packet_period in absolute time (so no event packet spans two chunks) and
/// memory stays bounded.
SimulationOutput runSimulation(const SimConfig& config, const EventChunkSink& sink = EventChunkSink());

/// Write the dataset folder (created when missing): events.txt from output.events plus
/// everything writeDatasetWithoutEvents writes. Throws std::runtime_error naming the file.
void writeDataset(const std::string& dir, const SimConfig& config, const SimulationOutput& output);
/// groundtruth.txt, calib.txt, camera_info.yaml, map.yaml, config.yaml (creates the folder).
void writeDatasetWithoutEvents(const std::string& dir, const SimConfig& config, const dvs_calibration::Trajectory& groundtruth);
/// imu.txt and imu_bias_groundtruth.txt (the folder must exist); throws dvs_driver::WriteError.
void writeImuFiles(const std::string& dir, const SimulationOutput& output);
/// The header line of imu_bias_groundtruth.txt.
extern const char* const kImuBiasHeader;

/// events.txt written chunk by chunk (for streaming sinks).
class EventsTextStream
{
public:
  /// Creates the file (checked_write.h: written beside it and renamed at close()); throws
  /// dvs_driver::WriteError naming it.
  explicit EventsTextStream(const std::string& path);
  ~EventsTextStream();
  /// Throws dvs_driver::WriteError when the disk refuses the chunk (full disk, ...).
  void write(const dvs_driver::EventVector& chunk);
  /// Flushes, checks and renames the file into place; throws dvs_driver::WriteError.
  void close();

private:
  std::unique_ptr<dvs_driver::CheckedFileWriter> out_;
};
}  // namespace dvs_screen_sim
