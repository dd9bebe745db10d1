#pragma once
// A recorded event file read piece by piece (ROS-free): the pull interface the replay streams
// from, so a recording of any size is never held in memory. One implementation per format:
// AedatFileSource (aedat_reader.h), TextFileSource (event_text_io.h), BagEventSource
// (event_bag_io.h, library dvs_driver_ros), MemoryEventSource (below: events already in memory).
#include <dvs_driver/event.h>
#include <dvs_driver/event_validation.h>

#include <memory>
#include <string>

namespace dvs_driver
{
/// What a source knows once it is open.
struct EventSourceInfo
{
  std::string name;           ///< the file (used in messages)
  uint32_t width = 0;         ///< sensor size; 0 when the file does not say (see scanSensorSize)
  uint32_t height = 0;
  std::string sensor_name;    ///< "DVS128", "DAVIS240", "DAVIS346" or ""
  std::string format;         ///< detected format, e.g. "AEDAT 2.0", "Prophesee RAW EVT 3.0" (for messages)
  int64_t expected_events = -1;  ///< events the file announces (AEDAT 4.0 data table), -1 unknown
  size_t truncated_bytes = 0; ///< bytes of an incomplete last record (ignored)
};

class EventSource
{
public:
  virtual ~EventSource() = default;
  virtual const EventSourceInfo& info() const = 0;
  /// Append up to `max_events` events (in time order, continuing where the last call stopped) to
  /// `out`; returns how many, 0 at the end. Throws EventFileError naming the file (and line or
  /// record) on malformed data.
  virtual size_t read(EventVector& out, size_t max_events) = 0;
  /// Start again at the first event.
  virtual void rewind() = 0;
  /// What the source itself repaired or dropped before delivering (since the last rewind), which
  /// a consumer cannot see in the events: e.g. AEDAT times clamped (with the steps back they
  /// repaired) and records outside the sensor. Consumers validate the delivered events with an
  /// EventValidator and merge these (FileReplay, convert). Default: nothing.
  virtual EventChecks checks() const { return EventChecks(); }
};

/// Opens an AEDAT 2.0 (`.aedat`, `.dat`) or events.txt file (anything else) for streaming.
/// Throws EventFileError naming the file when it cannot be opened or its header is malformed;
/// a `.bag` path throws (use openEventSource or BagEventSource, library dvs_driver_ros).
std::unique_ptr<EventSource> openEventFileSource(const std::string& path);

/// Events already in memory as a source.
class MemoryEventSource : public EventSource
{
public:
  MemoryEventSource(EventStream stream, const std::string& name);
  const EventSourceInfo& info() const override { return info_; }
  size_t read(EventVector& out, size_t max_events) override;
  void rewind() override { next_ = 0; }

private:
  EventStream stream_;
  EventSourceInfo info_;
  size_t next_ = 0;
};

/// Largest pixel coordinates seen so far; the sensor they fit (see inferSensorSize).
struct SensorBounds
{
  uint32_t max_x = 0, max_y = 0;
  void add(const Event* begin, const Event* end);
  /// Smallest known sensor (DVS128, DAVIS240, DAVIS346) holding every event added, else the
  /// bounding size. Returns the sensor name or "".
  std::string sensor(uint32_t& width, uint32_t& height) const;
};

/// What the start of a replay needs to know about its source.
struct SourceProbe
{
  bool empty = true;
  int64_t first_t_ns = 0;  ///< time of the first event (when not empty)
};

/// Reads the first event (rewinds after). When the source does not state its sensor size,
/// first reads the whole source once (in pieces: bounded memory) to find the smallest sensor
/// holding every event, and fills info width/height/sensor_name through `width`, `height`,
/// `sensor_name` (otherwise they are the source's). Throws what read() throws.
SourceProbe probeSource(EventSource& source, uint32_t& width, uint32_t& height, std::string& sensor_name);
}  // namespace dvs_driver
