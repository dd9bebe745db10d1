#include <dvs_driver/event_text_io.h>
#include <dvs_driver/imu_text_io.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_driver/checked_write.h>
#include <dvs_calibration/trajectory_file.h>

#include <ctime>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace dvs_screen_sim
{
SimulationOutput runSimulation(const SimConfig& config, const EventChunkSink& sink)
{
  SimulationOutput out;
  const auto trajectory = makeTrajectory(config);
  EventSimulator sim(config.camera, config.scene, config.events, config.sampling, config.seed);
  std::clock_t cpu = 0;
  std::clock_t c0 = std::clock();
  sim.start(*trajectory, 0.0, config.time_offset_ns);
  if (!sink)
  {
    sim.advanceTo(config.duration, out.events);
    sim.flush(out.events);
    cpu = std::clock() - c0;
    out.event_count = out.events.size();
  }
  else
  {
    // Chunk boundaries at multiples of chunk_ns in absolute (offset) time.
    const int64_t period_ns = std::max<int64_t>(1, std::llround(config.packet_period * 1e9));
    const int64_t chunk_ns = period_ns * std::max<int64_t>(1, 100000000 / period_ns);
    const int64_t end_ns = config.time_offset_ns + std::llround(config.duration * 1e9);
    dvs_driver::EventVector chunk;
    int64_t boundary = (config.time_offset_ns / chunk_ns + 1) * chunk_ns;
    for (bool last = false; !last; boundary += chunk_ns)
    {
      last = boundary >= end_ns;
      chunk.clear();
      c0 = std::clock();
      if (last)
      {
        sim.advanceTo(config.duration, chunk);
        sim.flush(chunk);
      }
      else
        sim.advanceTo(static_cast<double>(boundary - config.time_offset_ns) * 1e-9, chunk);
      cpu += std::clock() - c0;
      out.event_count += chunk.size();
      if (!chunk.empty())
        sink(chunk);
    }
  }
  out.cpu_seconds = static_cast<double>(cpu) / CLOCKS_PER_SEC;
  out.stats = sim.stats();
  out.groundtruth = sampleTrajectory(*trajectory, config.duration, config.groundtruth_rate);
  const double offset = static_cast<double>(config.time_offset_ns) * 1e-9;
  for (auto& sp : out.groundtruth)
    sp.t += offset;
  simulateImu(*trajectory, config.duration, config.imu, config.seed, config.time_offset_ns, out.imu, &out.imu_bias);
  return out;
}

EventsTextStream::EventsTextStream(const std::string& path) : out_(std::make_unique<dvs_driver::CheckedFileWriter>(path))
{
}

EventsTextStream::~EventsTextStream() = default;

void EventsTextStream::write(const dvs_driver::EventVector& chunk)
{
  dvs_driver::writeEventsText(out_->stream(), chunk);
  out_->write(nullptr, 0);  // throws WriteError now if the disk refused the chunk
}

void EventsTextStream::close() { out_->commit(); }

void writeDataset(const std::string& dir, const SimConfig& config, const SimulationOutput& output)
{
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw std::runtime_error("cannot create output folder '" + dir + "': " + ec.message());
  dvs_driver::writeEventsText(dir + "/events.txt", output.events);
  writeDatasetWithoutEvents(dir, config, output.groundtruth);
  writeImuFiles(dir, output);
}

const char* const kImuBiasHeader = "# t bax bay baz bgx bgy bgz: true IMU biases (s, m/s^2, rad/s) of each imu.txt sample\n";

void writeImuFiles(const std::string& dir, const SimulationOutput& output)
{
  dvs_driver::writeImuText(dir + "/imu.txt", output.imu);
  dvs_driver::writeImuText(dir + "/imu_bias_groundtruth.txt", output.imu_bias, kImuBiasHeader);
}

void writeDatasetWithoutEvents(const std::string& dir, const SimConfig& config, const dvs_calibration::Trajectory& groundtruth)
{
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw std::runtime_error("cannot create output folder '" + dir + "': " + ec.message());
  const std::string base = dir + "/";
  dvs_calibration::writeTumTrajectory(base + "groundtruth.txt", groundtruth, "t px py pz qx qy qz qw (T_world_camera)");
  dvs_calibration::saveCalibTxt(base + "calib.txt", config.camera);
  dvs_calibration::saveCameraInfoYaml(base + "camera_info.yaml", config.camera, "dvs_screen_sim");
  writeLineMapYaml(base + "map.yaml", config.scene);
  YAML::Emitter em;
  em.SetDoublePrecision(17);
  em << config.resolved;
  dvs_driver::writeFileChecked(base + "config.yaml", "# Resolved dvs_screen_sim configuration: `simulate --scenario " +
                                                       config.scenario + " --config config.yaml` reproduces this dataset.\n" +
                                                       em.c_str() + "\n");
}
}  // namespace dvs_screen_sim
