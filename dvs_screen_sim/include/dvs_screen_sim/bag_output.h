#pragma once
// A simulation as a rosbag (library dvs_screen_sim_ros), the topics of the live node:
//   /dvs/events               dvs_msgs/EventArray, packets of config.packet_period (1 ms)
//   /dvs/camera_info          sensor_msgs/CameraInfo, at t = 0 and every 0.1 s
//   /dvs/ground_truth/pose    geometry_msgs/PoseStamped (T_world_camera), at groundtruth_rate
//   /tf                       tf2_msgs/TFMessage world -> dvs_gt, at groundtruth_rate
//   /dvs/ground_truth/map     visualization_msgs/MarkerArray, at t = 0 and every 1 s
//   /dvs/imu                  sensor_msgs/Imu, the simulated IMU's samples (frame dvs)
// Bag record times = header stamps (a stamp of 0 is recorded at 1 ns: rosbag's minimum).
#include <dvs_screen_sim/dataset.h>

#include <memory>
#include <string>

namespace dvs_driver
{
class CheckedBagWriter;
}

namespace dvs_screen_sim
{
/// Streaming bag writer: events chunk by chunk (chunks must not split a packet period, as
/// runSimulation's chunks do not), then the other topics.
class SimulationBagWriter
{
public:
  /// Creates (overwrites) the bag; throws std::runtime_error naming it.
  SimulationBagWriter(const std::string& path, const SimConfig& config);
  ~SimulationBagWriter();
  void addEvents(const dvs_driver::EventVector& chunk);
  /// Writes camera_info, ground truth, TF, the map and the IMU samples, and closes the bag.
  void finish(const dvs_calibration::Trajectory& groundtruth, const dvs_driver::ImuVector& imu = {});

private:
  SimConfig config_;
  std::unique_ptr<dvs_driver::CheckedBagWriter> bag_;
};

/// The whole simulation output as a bag.
void writeSimulationBag(const std::string& path, const SimConfig& config, const SimulationOutput& output);
}  // namespace dvs_screen_sim
