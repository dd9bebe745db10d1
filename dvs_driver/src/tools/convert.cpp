// rosrun dvs_driver convert --input IN --output OUT [--zero-time] [--width W --height H]
//                           [--topic T] [--packet-period S]
// IN: .aedat (2.0), events.txt (or a .bag with dvs_msgs/EventArray); OUT: events.txt or .bag
// (topic /dvs/events, 1 ms packets). Prints a one-line JSON summary on stdout:
// {"events":N,"span_s":S,"width":W,"height":H,"sensor":"DVS128","skipped_words":K,...}
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_file.h>
#include <dvs_driver/event_text_io.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

namespace
{
void usage(std::ostream& os)
{
  os << "usage: convert --input IN --output OUT [options]\n"
        "  IN   .aedat (jAER AEDAT 2.0: DVS128, DAVIS240/346 DVS events), events.txt, or .bag\n"
        "  OUT  events.txt (any name not ending in .bag) or .bag (dvs_msgs/EventArray packets)\n"
        "options:\n"
        "  --topic T               bag topic (default /dvs/events)\n"
        "  --packet-period S       bag packet period in seconds (default 0.001)\n"
        "  --packet-period-ms P    deprecated: the same in milliseconds\n"
        "  --width W --height H    sensor size (default: from the file, else the smallest known\n"
        "                          sensor holding every event)\n"
        "  --zero-time             shift times so the first event is at t = 0 (needed to write\n"
        "                          negative AEDAT time stamps into a bag)\n"
        "Prints one JSON line: events, span_s, width, height, sensor, skipped_words.\n";
}

std::string jsonString(const std::string& s)
{
  std::string o = "\"";
  for (char c : s)
  {
    if (c == '"' || c == '\\')
      o += '\\';
    if (static_cast<unsigned char>(c) < 0x20)
      continue;
    o += c;
  }
  return o + "\"";
}

bool parsePositive(const char* s, double& v)
{
  char* end = nullptr;
  v = std::strtod(s, &end);
  return end && *end == '\0' && v > 0;
}
}  // namespace

int main(int argc, char** argv)
{
  std::string input, output, topic = dvs_driver::kDefaultEventTopic;
  double period_s = 0.001, width = 0, height = 0;
  bool zero_time = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc)
      {
        std::cerr << "convert: " << name << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--input")
      input = value("--input");
    else if (a == "--output")
      output = value("--output");
    else if (a == "--topic")
      topic = value("--topic");
    else if (a == "--zero-time")
      zero_time = true;
    else if (a == "--packet-period")
    {
      if (!parsePositive(value("--packet-period"), period_s))
      {
        std::cerr << "convert: --packet-period must be a positive number of seconds\n";
        return 2;
      }
    }
    else if (a == "--packet-period-ms")
    {
      double ms = 0;
      if (!parsePositive(value("--packet-period-ms"), ms))
      {
        std::cerr << "convert: --packet-period-ms must be a positive number\n";
        return 2;
      }
      std::cerr << "convert: --packet-period-ms is deprecated: use --packet-period " << ms * 1e-3 << " (seconds)\n";
      period_s = ms * 1e-3;
    }
    else if (a == "--width" || a == "--height")
    {
      double& v = a == "--width" ? width : height;
      if (!parsePositive(value(a.c_str()), v) || v != static_cast<uint32_t>(v))
      {
        std::cerr << "convert: " << a << " must be a positive integer\n";
        return 2;
      }
    }
    else if (a == "-h" || a == "--help")
    {
      usage(std::cout);
      return 0;
    }
    else if (a.rfind("__", 0) == 0)  // roslaunch/rosrun remapping arguments
      continue;
    else
    {
      std::cerr << "convert: unknown argument `" << a << "`\n";
      usage(std::cerr);
      return 2;
    }
  }
  if (input.empty() || output.empty())
  {
    std::cerr << "convert: --input and --output are required\n";
    usage(std::cerr);
    return 2;
  }
  if ((width > 0) != (height > 0))
  {
    std::cerr << "convert: give both --width and --height, or neither\n";
    return 2;
  }

  try
  {
    dvs_driver::EventFileContents in;
    if (dvs_driver::eventFileFormat(input) == dvs_driver::EventFileFormat::Bag)
      in.stream = dvs_driver::readEventsBag(input, topic);
    else
      in = dvs_driver::readEventFile(input);
    dvs_driver::EventStream& s = in.stream;
    if (width > 0)
    {
      s.width = static_cast<uint32_t>(width);
      s.height = static_cast<uint32_t>(height);
    }
    else if (s.width == 0 || s.height == 0)
    {
      const std::string name = dvs_driver::inferSensorSize(s.events, s.width, s.height);
      if (in.sensor_name.empty())
        in.sensor_name = name;
    }
    for (const dvs_driver::Event& e : s.events)
      if (e.x >= s.width || e.y >= s.height)
        throw dvs_driver::EventFileError(input + ": event at pixel (" + std::to_string(e.x) + ", " +
                                         std::to_string(e.y) + ") lies outside the " + std::to_string(s.width) +
                                         "x" + std::to_string(s.height) + " sensor");
    int64_t offset_ns = 0;
    if (zero_time && !s.events.empty())
    {
      offset_ns = -s.events.front().t_ns;
      for (dvs_driver::Event& e : s.events)
        e.t_ns += offset_ns;
    }
    size_t packets = 0;
    if (dvs_driver::eventFileFormat(output) == dvs_driver::EventFileFormat::Bag)
    {
      if (!s.events.empty() && s.events.front().t_ns < 0)
        throw dvs_driver::EventFileError(input + ": time stamps are negative (first " +
                                         std::to_string(s.events.front().t_ns) +
                                         " ns) and a bag cannot hold them: add --zero-time");
      packets = dvs_driver::writeEventsBag(output, topic, s, static_cast<int64_t>(period_s * 1e9 + 0.5));
    }
    else
      dvs_driver::writeEventsText(output, s.events);

    const double span = s.events.empty() ? 0.0 : (s.events.back().t_ns - s.events.front().t_ns) * 1e-9;
    char buf[512];
    std::snprintf(buf, sizeof(buf),
                  "{\"events\":%zu,\"span_s\":%.6f,\"width\":%u,\"height\":%u,\"sensor\":%s,\"skipped_words\":%llu,"
                  "\"truncated_bytes\":%zu,\"packets\":%zu,\"time_offset_ns\":%lld}",
                  s.events.size(), span, s.width, s.height, jsonString(in.sensor_name).c_str(),
                  static_cast<unsigned long long>(in.skipped), in.truncated_bytes, packets,
                  static_cast<long long>(offset_ns));
    std::cout << buf << std::endl;
  }
  catch (const std::exception& e)
  {
    std::cerr << "convert: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
