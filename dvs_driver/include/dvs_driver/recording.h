#pragma once
// Any recorded event file, its format detected from its bytes (library dvs_driver_ros: bags need
// rosbag): dvs_msgs bags, AEDAT 2.0 and events.txt (event_file.h), and the formats of
// formats/event_format.h (Prophesee RAW EVT 2.0/3.0, AEDAT 3.1 and 4.0, HDF5). The one entry
// point of the offline tools (convert, track_offline, calibrate); the driver's file source
// streams the same files through openEventSource (event_bag_io.h).
#include <dvs_driver/event_file.h>
#include <dvs_driver/progress_meter.h>

#include <string>
#include <vector>

namespace dvs_driver
{
struct Recording
{
  EventFileContents contents;         ///< events, size (0: unknown), sensor name, repairs and skips
  std::string format;                 ///< "events.txt", "AEDAT 2.0", "ROS bag", "Prophesee RAW EVT 3.0", ...
  std::vector<std::string> warnings;  ///< what the reader noticed (damaged packets, truncation, ...)
};

/// Read a whole recording (`topic` for bags) with its IMU samples when the format carries them
/// (contents.imu: AEDAT 2.0 DAVIS files, AEDAT 4.0 IMUS streams, bags: sensor_msgs/Imu on
/// imuTopicFor(topic), e.g. /dvs/imu beside /dvs/events, sorted by stamp). Throws EventFileError (or a subclass) naming the
/// file and the problem; a truncated file gives every complete event before the damage and a
/// warning with the byte offset. `progress` (optional, e.g. ProgressMeter::callback()) is called
/// between batches with the events and bytes read so far (the binary formats, bags of EventPacket
/// and events.txt; dvs_msgs bags report events only; AEDAT 2.0 is read in one piece).
Recording readRecording(const std::string& path, const std::string& topic = "/dvs/events",
                        const ReadProgress& progress = ReadProgress());

/// The IMU topic beside an event topic: its last name `events` replaced by `imu` ("/dvs/events"
/// -> "/dvs/imu"); "" when the event topic's last name is not `events`.
std::string imuTopicFor(const std::string& events_topic);
/// Every sensor_msgs/Imu of `topic` in a bag, sorted by stamp (none: empty). Throws EventFileError.
ImuVector readImuBag(const std::string& path, const std::string& topic);

/// The format readRecording / openEventSource will use for `path` (for messages).
std::string recordingFormatName(const std::string& path);
}  // namespace dvs_driver
