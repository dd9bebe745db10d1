#include <dvs_driver/event_file.h>
#include <dvs_driver/event_source.h>
#include <dvs_driver/event_text_io.h>

#include <algorithm>
#include <fstream>

namespace dvs_driver
{
namespace
{
bool endsWith(const std::string& s, const std::string& suffix)
{
  if (s.size() < suffix.size())
    return false;
  return std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}
}  // namespace

EventFileFormat eventFileFormat(const std::string& path)
{
  if (endsWith(path, ".aedat") || endsWith(path, ".dat"))
    return EventFileFormat::Aedat;
  if (endsWith(path, ".bag"))
    return EventFileFormat::Bag;
  // Any other name: an AEDAT 2.0 file or a bag still says so in its first bytes.
  char head[16] = {0};
  std::ifstream in(path, std::ios::binary);
  if (in)
    in.read(head, sizeof(head));
  const std::string start(head, static_cast<size_t>(in ? sizeof(head) : in.gcount()));
  if (start.compare(0, 10, "#!AER-DAT2") == 0)
    return EventFileFormat::Aedat;
  if (start.compare(0, 13, "#ROSBAG V2.0\n") == 0)
    return EventFileFormat::Bag;
  return EventFileFormat::Text;
}

EventFileContents readEventFile(const std::string& path)
{
  EventFileContents out;
  switch (eventFileFormat(path))
  {
    case EventFileFormat::Aedat:
    {
      AedatRecording rec = readAedat(path);
      out.stream = std::move(rec.stream);
      out.sensor_name = rec.info.sensor_name;
      out.skipped = rec.info.skippedRecords();
      out.truncated_bytes = rec.info.truncated_bytes;
      out.checks = rec.info.checks;
      out.aedat = rec.info;
      out.imu = std::move(rec.imu);
      break;
    }
    case EventFileFormat::Text:
      out.stream.events = readEventsText(path);
      break;
    case EventFileFormat::Bag:
      throw EventFileError(path + ": bags are read with dvs_driver::readEventsBag (library dvs_driver_ros)");
  }
  return out;
}

std::string inferSensorSize(const EventVector& events, uint32_t& width, uint32_t& height)
{
  SensorBounds bounds;
  bounds.add(events.data(), events.data() + events.size());
  return bounds.sensor(width, height);
}
}  // namespace dvs_driver
