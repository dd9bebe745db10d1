#pragma once
// One entry point for recorded event files (ROS-free): AEDAT 2.0 (`.aedat`) or Event Camera
// Dataset text (`.txt`). Bags are read by event_bag_io.h (library dvs_driver_ros).
#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/event.h>
#include <dvs_driver/imu_sample.h>

#include <string>

namespace dvs_driver
{
enum class EventFileFormat
{
  Aedat,
  Text,
  Bag
};

/// Format from the file name (`.aedat`/`.dat` -> Aedat, `.bag` -> Bag), else from its first bytes
/// (`#!AER-DAT2` -> Aedat, `#ROSBAG V2.0` -> Bag), else Text. The other formats:
/// formats/event_format.h (detectEventFormat), all together: recording.h.
EventFileFormat eventFileFormat(const std::string& path);

struct EventFileContents
{
  EventStream stream;        ///< width/height 0 when the file does not say (see inferSensorSize)
  std::string sensor_name;   ///< "DVS128", "DAVIS240", "DAVIS346" or "" (text files)
  uint64_t skipped = 0;      ///< records/words read but not returned as events
  size_t truncated_bytes = 0;
  AedatInfo aedat;           ///< AEDAT files: what the reader found (skipped records by kind, ...)
  ImuVector imu;             ///< IMU samples the file carries (AEDAT 2.0 DAVIS, AEDAT 4.0), else empty
  /// What the reader repaired or dropped itself (AEDAT: clamped times, records outside the
  /// sensor); validate the events for the rest (EventValidator).
  EventChecks checks;
};

/// Read an AEDAT 2.0 or events.txt file (throws EventFileError / AedatError with a clear message;
/// a `.bag` path throws: use readEventsBag).
EventFileContents readEventFile(const std::string& path);

/// Smallest known sensor (DVS128 128x128, DAVIS240 240x180, DAVIS346 346x260) holding every
/// event; else the bounding size (max x + 1, max y + 1). Returns the sensor name or "".
std::string inferSensorSize(const EventVector& events, uint32_t& width, uint32_t& height);
}  // namespace dvs_driver
