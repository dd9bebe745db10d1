#include <dvs_driver/recording.h>

#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_packet_bag.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/formats/event_format.h>
#include <dvs_driver/imu_msg.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <algorithm>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sys/stat.h>

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

std::string imuTopicFor(const std::string& events_topic)
{
  const size_t slash = events_topic.rfind('/');
  const std::string last = slash == std::string::npos ? events_topic : events_topic.substr(slash + 1);
  if (last != "events")
    return "";
  return events_topic.substr(0, slash == std::string::npos ? 0 : slash + 1) + "imu";
}

ImuVector readImuBag(const std::string& path, const std::string& topic)
{
  ImuVector imu;
  try
  {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic)))
      if (const auto msg = m.instantiate<sensor_msgs::Imu>())
        imu.push_back(fromImuMessage(*msg));
  }
  catch (const rosbag::BagException& e)
  {
    throw EventFileError(path + ": cannot read the IMU topic " + topic + ": " + e.what());
  }
  std::stable_sort(imu.begin(), imu.end(), [](const ImuSample& a, const ImuSample& b) { return a.t_ns < b.t_ns; });
  return imu;
}

std::string recordingFormatName(const std::string& path)
{
  if (eventFileFormat(path) == EventFileFormat::Bag || detectEventFormat(path) == EventFormat::RosBag1)
  {
    auto packets = openEventPacketBagFor(path);
    return packets ? packets->formatName() : "ROS bag";
  }
  const EventFormat f = detectEventFormat(path);
  if (f == EventFormat::Unknown)
    return "events.txt";
  return eventFormatName(f);
}

Recording readRecording(const std::string& path, const std::string& topic, const ReadProgress& progress)
{
  Recording r;
  const EventFormat f = eventFileFormat(path) == EventFileFormat::Bag ? EventFormat::RosBag1 : detectEventFormat(path);
  std::unique_ptr<EventFileReader> reader;
  if (f == EventFormat::RosBag1)
    reader = openEventPacketBagFor(path, topic);  // a bag of event_camera_msgs/EventPacket
  if (f == EventFormat::RosBag1 && !reader)
  {
    r.format = "ROS bag";
    BagEventSource source(path, topic);
    EventStream& s = r.contents.stream;
    s.width = source.info().width;
    s.height = source.info().height;
    while (source.read(s.events, 1 << 16) > 0)
      if (progress)
        progress(s.events.size(), 0, 0);
    const std::string imu_topic = imuTopicFor(topic);
    if (!imu_topic.empty())
      r.contents.imu = readImuBag(path, imu_topic);
    return r;
  }
  if (!reader && !readByFormatReader(f))
  {
    // AEDAT 2.0 or events.txt (by its extension, as before: a text file has no signature).
    if (eventFileFormat(path) == EventFileFormat::Text && progress)
    {
      std::ifstream in(path);
      if (!in)
        throw EventFileError(path + ": cannot open events file: " + std::strerror(errno));
      struct stat st{};
      const uint64_t size = ::stat(path.c_str(), &st) == 0 ? uint64_t(st.st_size) : 0;
      r.contents.stream.events = readEventsText(in, path, progress, size);
    }
    else
      r.contents = readEventFile(path);
    r.format = eventFileFormat(path) == EventFileFormat::Aedat ? "AEDAT 2.0" : "events.txt";
    return r;
  }
  if (!reader)
    reader = openEventFileReader(path);
  r.format = reader->formatName();
  EventVector& events = r.contents.stream.events;
  if (reader->expectedEvents() > 0)
    events.reserve(static_cast<size_t>(reader->expectedEvents()));
  while (reader->read(events, 1 << 16))
  {
    reader->takeImu(r.contents.imu);  // bounded in the reader: taken after every read
    if (progress)
    {
      const ReaderStats s = reader->stats();
      progress(events.size(), s.bytes_read, s.file_size);
    }
  }
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
