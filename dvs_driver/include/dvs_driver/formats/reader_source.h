#pragma once
// A format reader (event_format.h) as the driver's EventSource, so that the file replay
// (FileReplay, the driver's ~file) streams every format the readers know.
#include <dvs_driver/event_source.h>
#include <dvs_driver/formats/event_format.h>

#include <functional>
#include <memory>
#include <string>

namespace dvs_driver
{
class FormatReaderSource : public EventSource
{
public:
  /// Opens `path` with openEventFileReader (throws EventFormatError naming the file).
  explicit FormatReaderSource(const std::string& path);
  /// Any reader: `open` makes a reader at the first event (called now and on every rewind),
  /// e.g. openEventPacketBag for ROS 1 bags of event_camera_msgs/EventPacket.
  FormatReaderSource(const std::string& path, std::function<std::unique_ptr<EventFileReader>()> open);
  const EventSourceInfo& info() const override { return info_; }
  size_t read(EventVector& out, size_t max_events) override;
  /// Reopens the file at its first event.
  void rewind() override;
  /// What the reader dropped itself: events outside the sensor (counted as outside_sensor).
  EventChecks checks() const override;

private:
  std::string path_;
  std::function<std::unique_ptr<EventFileReader>()> open_;
  std::unique_ptr<EventFileReader> reader_;
  EventSourceInfo info_;
};
}  // namespace dvs_driver
