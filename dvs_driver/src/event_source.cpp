#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/event_file.h>
#include <dvs_driver/event_source.h>
#include <dvs_driver/event_text_io.h>

#include <algorithm>
#include <sys/stat.h>

namespace dvs_driver
{
std::unique_ptr<EventSource> openEventFileSource(const std::string& path)
{
  struct stat st;
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    throw EventFileError(path + ": is a directory, not an event file");
  switch (eventFileFormat(path))
  {
    case EventFileFormat::Aedat:
      return std::unique_ptr<EventSource>(new AedatFileSource(path));
    case EventFileFormat::Text:
      return std::unique_ptr<EventSource>(new TextFileSource(path));
    case EventFileFormat::Bag:
      break;
  }
  throw EventFileError(path + ": bags are streamed by dvs_driver::openEventSource / BagEventSource (library dvs_driver_ros)");
}

MemoryEventSource::MemoryEventSource(EventStream stream, const std::string& name) : stream_(std::move(stream))
{
  info_.name = name;
  info_.format = "events in memory";
  info_.width = stream_.width;
  info_.height = stream_.height;
}

size_t MemoryEventSource::read(EventVector& out, size_t max_events)
{
  const size_t n = std::min(max_events, stream_.events.size() - next_);
  out.insert(out.end(), stream_.events.begin() + static_cast<long>(next_),
             stream_.events.begin() + static_cast<long>(next_ + n));
  next_ += n;
  return n;
}

void SensorBounds::add(const Event* begin, const Event* end)
{
  for (const Event* e = begin; e != end; ++e)
  {
    max_x = std::max<uint32_t>(max_x, e->x);
    max_y = std::max<uint32_t>(max_y, e->y);
  }
}

std::string SensorBounds::sensor(uint32_t& width, uint32_t& height) const
{
  struct Known
  {
    const char* name;
    uint32_t w, h;
  } known[] = {{"DVS128", 128, 128}, {"DAVIS240", 240, 180}, {"DAVIS346", 346, 260}};
  for (const Known& k : known)
    if (max_x < k.w && max_y < k.h)
    {
      width = k.w;
      height = k.h;
      return k.name;
    }
  width = max_x + 1;
  height = max_y + 1;
  return "";
}

SourceProbe probeSource(EventSource& source, uint32_t& width, uint32_t& height, std::string& sensor_name)
{
  SourceProbe probe;
  width = source.info().width;
  height = source.info().height;
  sensor_name = source.info().sensor_name;
  EventVector block;
  block.reserve(4096);
  source.rewind();
  if (width == 0 || height == 0)
  {
    SensorBounds bounds;
    while (source.read(block, 4096) > 0)
    {
      if (probe.empty)
      {
        probe.empty = false;
        probe.first_t_ns = block.front().t_ns;
      }
      bounds.add(block.data(), block.data() + block.size());
      block.clear();
    }
    const std::string name = bounds.sensor(width, height);
    if (sensor_name.empty())
      sensor_name = name;
  }
  else if (source.read(block, 1) > 0)
  {
    probe.empty = false;
    probe.first_t_ns = block.front().t_ns;
  }
  source.rewind();
  return probe;
}
}  // namespace dvs_driver
