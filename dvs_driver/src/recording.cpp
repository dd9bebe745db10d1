#include <dvs_driver/recording.h>

#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/formats/event_format.h>

namespace dvs_driver
{
namespace
{
bool readByFormatReader(EventFormat f)
{
  return f == EventFormat::Aedat3 || f == EventFormat::Aedat4 || f == EventFormat::PropheseeRaw ||
         f == EventFormat::Hdf5;
}
}  // namespace

std::string recordingFormatName(const std::string& path)
{
  if (eventFileFormat(path) == EventFileFormat::Bag)
    return "ROS bag";
  const EventFormat f = detectEventFormat(path);
  if (f == EventFormat::Unknown)
    return "events.txt";
  return eventFormatName(f);
}

Recording readRecording(const std::string& path, const std::string& topic)
{
  Recording r;
  const EventFormat f = eventFileFormat(path) == EventFileFormat::Bag ? EventFormat::RosBag1 : detectEventFormat(path);
  if (f == EventFormat::RosBag1 || eventFileFormat(path) == EventFileFormat::Bag)
  {
    r.format = "ROS bag";
    r.contents.stream = readEventsBag(path, topic);
    return r;
  }
  if (!readByFormatReader(f))
  {
    // AEDAT 2.0 or events.txt (by its extension, as before: a text file has no signature).
    r.contents = readEventFile(path);
    r.format = eventFileFormat(path) == EventFileFormat::Aedat ? "AEDAT 2.0" : "events.txt";
    return r;
  }
  auto reader = openEventFileReader(path);
  r.format = reader->formatName();
  EventVector& events = r.contents.stream.events;
  if (reader->expectedEvents() > 0)
    events.reserve(static_cast<size_t>(reader->expectedEvents()));
  while (reader->read(events, 1 << 20))
    reader->takeImu(r.contents.imu);  // bounded in the reader: taken after every read
  reader->takeImu(r.contents.imu);
  r.contents.stream.width = reader->width();
  r.contents.stream.height = reader->height();
  r.contents.sensor_name = reader->formatName();
  const ReaderStats s = reader->stats();
  r.contents.skipped = s.unknown_words + s.invalid_events + s.damaged_packets + s.before_time;
  r.contents.truncated_bytes = s.truncated_bytes;
  r.contents.checks.outside_sensor = s.out_of_range;  // dropped by the reader itself, counted
  r.contents.checks.width = reader->width();
  r.contents.checks.height = reader->height();
  r.warnings = s.warnings;
  if (s.truncated)
    r.warnings.push_back("the file ends inside a record at byte " + std::to_string(s.truncated_offset) + " (" +
                         std::to_string(s.truncated_bytes) + " bytes ignored; every complete event before is read)");
  return r;
}
}  // namespace dvs_driver
