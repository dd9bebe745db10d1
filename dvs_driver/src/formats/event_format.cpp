#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/formats/aedat3.h>
#include <dvs_driver/formats/aedat4.h>
#include <dvs_driver/formats/event_format.h>
#include <dvs_driver/formats/hdf5_events.h>
#include <dvs_driver/formats/prophesee_raw.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace dvs_driver
{
EventFileReader::~EventFileReader() = default;

size_t EventFileReader::takeTriggers(std::vector<TriggerEvent>&)
{
  return 0;
}

size_t EventFileReader::takeImu(std::vector<ImuSample>&)
{
  return 0;
}

EventVector EventFileReader::readAll()
{
  EventVector all;
  while (read(all, size_t(1) << 20))
  {
  }
  return all;
}

EventFormat detectEventFormat(const uint8_t* d, size_t n)
{
  auto starts = [&](const char* s) { return n >= std::strlen(s) && std::memcmp(d, s, std::strlen(s)) == 0; };
  if (starts("#!AER-DAT4."))
    return EventFormat::Aedat4;
  if (starts("#!AER-DAT3."))
    return EventFormat::Aedat3;
  if (starts("#!AER-DAT2.") || starts("#!AER-DAT1."))
    return EventFormat::Aedat2;
  if (starts("% "))
    return EventFormat::PropheseeRaw;
  if (starts("#ROSBAG V2.0"))
    return EventFormat::RosBag1;
  if (n >= 8 && std::memcmp(d, "\x89HDF\r\n\x1a\n", 8) == 0)
    return EventFormat::Hdf5;
  if (n >= 16 && std::memcmp(d, "SQLite format 3", 16) == 0)
    return EventFormat::Sqlite;
  return EventFormat::Unknown;
}

EventFormat detectEventFormat(const std::string& path)
{
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f)
    throw EventFormatError(path + ": cannot open (" + std::strerror(errno) + ")");
  uint8_t head[32];
  const size_t n = std::fread(head, 1, sizeof head, f);
  std::fclose(f);
  return detectEventFormat(head, n);
}

const char* eventFormatName(EventFormat f)
{
  switch (f)
  {
    case EventFormat::Aedat2:
      return "AEDAT 2.0";
    case EventFormat::Aedat3:
      return "AEDAT 3.x";
    case EventFormat::Aedat4:
      return "AEDAT 4.0";
    case EventFormat::PropheseeRaw:
      return "Prophesee RAW";
    case EventFormat::RosBag1:
      return "ROS 1 bag";
    case EventFormat::Hdf5:
      return "HDF5";
    case EventFormat::Sqlite:
      return "SQLite (ROS 2 bag?)";
    default:
      return "unknown";
  }
}

namespace
{
/// AEDAT 2.0 through the existing whole-file reader (aedat_reader.h), served in pieces.
class Aedat2Reader : public EventFileReader
{
public:
  explicit Aedat2Reader(const std::string& path) : rec_(readAedat(path))
  {
    stats_.file_size = stats_.bytes_read = rec_.info.data_offset + rec_.info.records * 8 + rec_.info.truncated_bytes;
    stats_.other_words = rec_.info.sync_events + rec_.info.aps_samples + rec_.info.imu_samples;
    stats_.out_of_range = rec_.info.out_of_range;
    stats_.time_wraps = rec_.info.timestamp_wraps;
    stats_.time_backsteps = rec_.info.non_monotonic;
    stats_.imu_samples = rec_.info.imu_decoded;
    if (rec_.info.truncated_bytes > 0)
    {
      stats_.truncated = true;
      stats_.truncated_bytes = rec_.info.truncated_bytes;
      stats_.truncated_offset = rec_.info.data_offset + rec_.info.records * 8;
      stats_.warnings.push_back("truncated: the file ends inside a record at byte " +
                                std::to_string(stats_.truncated_offset));
    }
  }
  bool read(EventVector& out, size_t max_events) override
  {
    const auto& ev = rec_.stream.events;
    const size_t n = std::min(max_events, ev.size() - pos_);
    out.insert(out.end(), ev.begin() + pos_, ev.begin() + pos_ + n);
    pos_ += n;
    stats_.events += n;
    return n > 0;
  }
  uint32_t width() const override { return rec_.stream.width; }
  uint32_t height() const override { return rec_.stream.height; }
  std::string formatName() const override { return "AEDAT 2.0 (" + rec_.info.sensor_name + ")"; }
  ReaderStats stats() const override { return stats_; }
  size_t takeImu(std::vector<ImuSample>& out) override
  {
    const size_t n = rec_.imu.size();
    out.insert(out.end(), rec_.imu.begin(), rec_.imu.end());
    rec_.imu.clear();
    rec_.imu.shrink_to_fit();
    return n;
  }

private:
  AedatRecording rec_;
  size_t pos_ = 0;
  ReaderStats stats_;
};
}  // namespace

std::unique_ptr<EventFileReader> openEventFileReader(const std::string& path)
{
  const EventFormat f = detectEventFormat(path);
  switch (f)
  {
    case EventFormat::PropheseeRaw:
      return formats::openPropheseeRaw(path);
    case EventFormat::Aedat4:
      return formats::openAedat4(path);
    case EventFormat::Aedat3:
      return formats::openAedat3(path);
    case EventFormat::Aedat2:
      try
      {
        return std::make_unique<Aedat2Reader>(path);
      }
      catch (const EventFormatError&)
      {
        throw;
      }
      catch (const EventFileError& e)
      {
        throw EventFormatError(e.what());
      }
    case EventFormat::Hdf5:
      return formats::openHdf5Events(path);
    case EventFormat::RosBag1:
    case EventFormat::Sqlite:
      throw EventFormatError(path + ": " + eventFormatName(f) + " files are not read by openEventFileReader" +
                             (f == EventFormat::RosBag1 ? " (dvs_msgs bags: event_bag_io.h)" : ""));
    default:
      throw EventFormatError(path + ": unknown event file format (not AEDAT 2.0/3.1/4.0 or Prophesee RAW by its "
                                    "first bytes)");
  }
}
}  // namespace dvs_driver
