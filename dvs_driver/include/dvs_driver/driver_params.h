#pragma once
// The driver's parameters (ROS-free): one struct and the one table (name, field, unit, bounds,
// documentation) that reads them from ROS (DriverRos), validates them, and prints the README's
// parameter table (test_driver_params checks the README against it).
#include <dvs_driver/param_table.h>

#include <cstdint>
#include <string>
#include <vector>

namespace dvs_driver
{
struct DriverParams
{
  std::string serial_number;
  std::string file;
  double replay_speed = 1.0;
  bool replay_loop = false;
  bool wait_for_subscriber = false;
  std::string file_time = "replay";
  std::string bias_preset = "fast";
  double packet_period = 0.001;
  int max_events = 100000;
  bool master = true;
  double reset_timestamps_delay = -1.0;
  std::string frame_id = "dvs";
  std::string camera_name;
  std::string camera_info_url;
  double camera_info_rate = 30.0;
  double reconnect_interval = 0.5;
  int transfers = 8;
  int transfer_size = 4096;
  int queue_size = -1;
  int replay_queue_events = 262144;

  int64_t packetPeriodNs() const { return static_cast<int64_t>(packet_period * 1e9 + 0.5); }
  /// Packets per subscriber that ROS holds for a slow subscriber (0 = unlimited): ~queue_size,
  /// or automatic (-1): unlimited for a recording played once, 1000 otherwise.
  size_t publisherQueueSize() const;
};

/// The table over `p` (which must outlive it).
ParamTable driverParamTable(DriverParams& p);

/// Names legitimately set in the driver's namespace besides the table: the 12 biases (read by
/// dynamic_reconfigure) and the deprecated `packet_period_ms`.
std::vector<std::string> driverAlsoKnownParams();

/// The deprecated alias: milliseconds -> `packet_period` seconds.
constexpr const char* kDeprecatedPacketPeriodMs = "packet_period_ms";
}  // namespace dvs_driver
