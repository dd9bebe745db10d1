// rosrun dvs_driver convert --input IN --output OUT [--zero-time] [--width W --height H]
//                           [--topic T] [--packet-period S] [--imu IMU.txt]
// IN: any recording (recording.h: AEDAT 2.0/3.1/4.0, Prophesee RAW, HDF5, dvs_msgs bags,
// events.txt); OUT by extension: .aedat4, .raw (EVT 3.0), .h5/.hdf5, .bag (1 ms packets), else events.txt. Prints a one-line JSON summary on stdout:
// {"events":N,"span_s":S,"width":W,"height":H,"sensor":"DVS128","skipped_words":K,...}
// Bad input: a message naming the file and the problem, exit status 1; bad usage: status 2.
#include <dvs_driver/checked_write.h>
#include <dvs_driver/command_line.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_file.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/event_validation.h>
#include <dvs_driver/imu_text_io.h>
#include <dvs_driver/formats/aedat4.h>
#include <dvs_driver/formats/hdf5_events.h>
#include <dvs_driver/formats/prophesee_raw.h>
#include <dvs_driver/progress_meter.h>
#include <dvs_driver/recording.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <sys/stat.h>

namespace
{
struct Options
{
  std::string input, output, topic = dvs_driver::kDefaultEventTopic;
  std::string imu;  ///< imu.txt to write the recording's IMU samples to ("" = none)
  double period_s = 0.001, period_ms = 1.0;
  int width = 0, height = 0;
  bool zero_time = false;
};

// The options, their units and limits: parsed and checked by dvs_driver::parseCommandLine.
dvs_driver::ParamTable optionTable(Options& o)
{
  dvs_driver::ParamTable t("convert");
  t.add("--input", o.input, {}, "the recording, any readable format (detected from its bytes)");
  t.add("--output", o.output, {}, "by its extension: .aedat4, .raw, .h5/.hdf5, .bag, else events.txt");
  t.add("--topic", o.topic, {}, "bag topic");
  t.add("--packet-period", o.period_s, "s", 1e-6, 3600, "bag packet period");
  t.add("--packet-period-ms", o.period_ms, "ms", 1e-3, 3.6e6, "deprecated: the bag packet period in milliseconds");
  t.add("--width", o.width, "px", 0, 65536, "sensor width; 0 = from the file");
  t.add("--height", o.height, "px", 0, 65536, "sensor height; 0 = from the file");
  t.add("--zero-time", o.zero_time, "shift times so that the first event is at t = 0");
  t.add("--imu", o.imu, {}, "also write the recording's IMU samples to this imu.txt (t ax ay az gx gy gz)");
  t.addRule([&o] {
    return (o.width > 0) != (o.height > 0) ? "give both --width and --height, or neither" : "";
  });
  t.addRule([&o] {
    return o.input.empty() || o.output.empty() ? "--input and --output are required" : "";
  });
  return t;
}

/// The output format from the output's extension: aedat4, raw (EVT 3.0), hdf5, bag or text.
std::string outputFormat(const std::string& path)
{
  auto ends = [&](const char* ext) {
    const std::string e(ext);
    return path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
  };
  if (ends(".aedat4"))
    return "aedat4";
  if (ends(".raw"))
    return "raw";
  if (ends(".h5") || ends(".hdf5"))
    return "hdf5";
  if (ends(".bag"))
    return "bag";
  return "text";
}

void usage(std::ostream& os)
{
  os << "usage: convert --input IN --output OUT [options]\n"
        "  IN   any recording, its format detected from its bytes: AEDAT 2.0 / 3.1 / 4.0, Prophesee RAW\n"
        "       (EVT 2.0 / 3.0), HDF5 (DSEC or flat x,y,t,p), a .bag of dvs_msgs/EventArray, events.txt\n"
        "  OUT  by its extension: .aedat4 (AEDAT 4.0, LZ4), .raw (Prophesee EVT 3.0), .h5/.hdf5 (flat\n"
        "       x,y,t,p), .bag (dvs_msgs/EventArray packets), anything else events.txt\n"
        "options:\n"
        "  --topic T               bag topic (default /dvs/events)\n"
        "  --packet-period S       bag packet period in seconds (default 0.001, 1e-6 to 3600)\n"
        "  --packet-period-ms P    deprecated: the same in milliseconds\n"
        "  --width W --height H    sensor size, 1 to 65536 (default: from the file, else the\n"
        "                          smallest known sensor holding every event)\n"
        "  --zero-time             shift times so the first event is at t = 0 (needed to write\n"
        "                          negative AEDAT time stamps into a bag)\n"
        "  --imu IMU.txt           also write the IMU samples (AEDAT 2.0 DAVIS, AEDAT 4.0 IMUS, a bag's\n"
        "                          sensor_msgs/Imu beside the events topic, e.g. /dvs/imu) as\n"
        "                          imu.txt: t ax ay az gx gy gz in s, m/s^2, rad/s, the IMU's axes,\n"
        "                          same time base as the events (--zero-time shifts both)\n"
        "Prints one JSON line: events, span_s, width, height, sensor, skipped_words, ..., and the\n"
        "input checks (outside_sensor, backwards, max_backwards_s, clamped, duplicates).\n";
}

std::string num(unsigned long long v)
{
  return std::to_string(v);
}

// MemAvailable of /proc/meminfo in bytes (0 when unknown).
uint64_t availableMemory()
{
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kb = 0;
  std::string unit;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:")
      return kb * 1024;
  return 0;
}

// convert holds the whole recording: refuse up front, with the estimate, an input whose events
// would not fit in the memory available (at most one event per 8-byte AEDAT record, per 13-byte
// bag event, per 18-byte events.txt line; 16 bytes per event, plus the AEDAT file's bytes).
void checkMemory(const std::string& input)
{
  struct stat st;
  if (::stat(input.c_str(), &st) != 0 || !S_ISREG(st.st_mode))
    return;  // the reader names the problem
  const uint64_t size = static_cast<uint64_t>(st.st_size);
  uint64_t need = 0;
  switch (dvs_driver::eventFileFormat(input))
  {
    case dvs_driver::EventFileFormat::Aedat:
      need = size + size / 8 * 16;
      break;
    case dvs_driver::EventFileFormat::Bag:
      // dvs_msgs: 13 bytes per event; event_camera_msgs/EventPacket (EVT 3.0): 2 bytes or more
      need = dvs_driver::openEventPacketBagFor(input) ? size * 8 : size / 13 * 16;
      break;
    case dvs_driver::EventFileFormat::Text:
      need = size / 18 * 16;
      break;
  }
  const uint64_t avail = availableMemory();
  if (avail > 0 && need > avail)
    throw std::runtime_error(input + ": converting it needs up to " + num(need >> 20) + " MiB of memory (" +
                             num(size >> 20) + " MiB file), only " + num(avail >> 20) +
                             " MiB are available; convert a shorter piece");
}
/// A format writer fed in pieces of 2^20 events, so that a long write reports its progress.
template <class Writer>
void writeInPieces(Writer& w, const dvs_driver::EventVector& events, const dvs_driver::WriteProgress& progress)
{
  constexpr size_t kPiece = size_t(1) << 20;
  for (size_t i = 0; i < events.size(); i += kPiece)
  {
    const size_t n = std::min(kPiece, events.size() - i);
    w.write(events.data() + i, n);
    progress(i + n);
  }
  w.close();
}
}  // namespace

int main(int argc, char** argv)
{
  Options o;
  std::vector<std::string> given;
  try
  {
    dvs_driver::ParamTable table = optionTable(o);
    if (dvs_driver::parseCommandLine(table, argc, argv, &given))
    {
      usage(std::cout);
      return 0;
    }
  }
  catch (const dvs_driver::UsageError& e)
  {
    std::cerr << e.what() << "\n";
    usage(std::cerr);
    return 2;
  }
  for (const std::string& g : given)
    if (g == "--packet-period-ms")
    {
      std::cerr << "convert: --packet-period-ms is deprecated: use --packet-period " << o.period_ms * 1e-3
                << " (seconds)\n";
      o.period_s = o.period_ms * 1e-3;
    }
  const std::string& input = o.input;
  const std::string& output = o.output;

  try
  {
    checkMemory(input);
    // Any recording, its format detected from its bytes (recording.h).
    // Progress (events, percent of the file, rate) on stderr only when it is a terminal.
    dvs_driver::ProgressMeter meter("convert: reading " + input, 0);
    dvs_driver::Recording recording =
        dvs_driver::readRecording(input, o.topic, meter.enabled() ? meter.callback() : dvs_driver::ReadProgress());
    {
      struct stat st;
      meter.finish(recording.contents.stream.events.size(),
                   ::stat(input.c_str(), &st) == 0 ? static_cast<uint64_t>(st.st_size) : 0);
    }
    dvs_driver::EventFileContents& in = recording.contents;
    for (const std::string& w : recording.warnings)
      std::cerr << "convert: warning: " << input << ": " << w << "\n";
    dvs_driver::EventStream& s = in.stream;
    if (o.width > 0)
    {
      s.width = static_cast<uint32_t>(o.width);
      s.height = static_cast<uint32_t>(o.height);
    }
    else if (s.width == 0 || s.height == 0)
    {
      const std::string name = dvs_driver::inferSensorSize(s.events, s.width, s.height);
      if (in.sensor_name.empty())
        in.sensor_name = name;
    }

    // The one validation step: events outside the sensor, backwards times, duplicates; plus
    // what the reader repaired or skipped itself (AEDAT: clamped times, records outside).
    dvs_driver::EventValidator validator(s.width, s.height);
    size_t first_outside = s.events.size(), first_backwards = s.events.size();
    for (size_t i = 0; i < s.events.size(); ++i)
    {
      const uint64_t back = validator.checks().backwards;
      if (!validator.check(s.events[i]) && first_outside == s.events.size())
        first_outside = i;
      if (validator.checks().backwards != back && first_backwards == s.events.size())
        first_backwards = i;
    }
    const dvs_driver::EventChecks& found = validator.checks();
    if (found.outside_sensor > 0)
    {
      const dvs_driver::Event& e = s.events[first_outside];
      throw dvs_driver::EventFileError(input + ": " + num(found.outside_sensor) +
                                       (found.outside_sensor == 1 ? " event lies" : " events lie") + " outside the " +
                                       std::to_string(s.width) + "x" + std::to_string(s.height) +
                                       " sensor (the first, event " + num(first_outside) + ", at pixel (" +
                                       std::to_string(e.x) + ", " + std::to_string(e.y) + "))");
    }
    // events.txt and bags must be in time order (their readers refuse anything else); the
    // binary formats keep the file's order (real EVT 3.0 files step back by a few us), warned.
    const std::string out_kind = outputFormat(output);
    if (found.backwards > 0 && (out_kind == "text" || out_kind == "bag"))
      throw dvs_driver::EventFileError(input + ": time goes backwards at " + num(found.backwards) +
                                       (found.backwards == 1 ? " event" : " events") + " (by up to " +
                                       std::to_string(found.max_backwards_ns * 1e-9) + " s; the first at event " +
                                       num(first_backwards) + ", t = " +
                                       std::to_string(s.events[first_backwards].t_ns * 1e-9) +
                                       " s): events.txt and bags need events in time order");
    dvs_driver::EventChecks checks = in.checks;
    checks.merge(found);
    if (!checks.clean())
      std::cerr << "convert: warning: " << input << ": " << checks.summary() << "\n";
    const dvs_driver::AedatInfo& a = in.aedat;
    const bool aedat = dvs_driver::eventFileFormat(input) == dvs_driver::EventFileFormat::Aedat;
    if (aedat && a.records > 0 && (a.out_of_range > 0 || s.events.empty()))
      std::cerr << "convert: warning: " << input << ": " << a.records << " records, " << s.events.size()
                << " events; skipped: " << a.out_of_range << " outside the " << a.sensor_name << " sensor, "
                << a.sync_events << " sync, " << a.aps_samples << " APS, " << a.imu_samples
                << " IMU (not a " << a.sensor_name << " recording, or corrupt?)\n";
    if (in.truncated_bytes > 0)
      std::cerr << "convert: warning: " << input << ": " << in.truncated_bytes
                << " bytes of an incomplete last record ignored\n";

    int64_t offset_ns = 0;
    if (o.zero_time && !s.events.empty())
    {
      offset_ns = -s.events.front().t_ns;
      for (dvs_driver::Event& e : s.events)
        e.t_ns += offset_ns;
    }
    size_t packets = 0;
    const std::string out_format = outputFormat(output);
    // Progress of the write (events, percent of them, rate), again on a terminal only.
    dvs_driver::ProgressMeter write_meter("convert: writing " + output, 0);
    write_meter.setTotalEvents(s.events.size());
    if (out_format == "aedat4" || out_format == "raw" || out_format == "hdf5")
    {
      // The writers of the format readers (exact round trips; times in microseconds).
      if (!s.events.empty() && s.events.front().t_ns < 0)
        throw dvs_driver::EventFileError(input + ": time stamps are negative (first " +
                                         std::to_string(s.events.front().t_ns) + " ns): add --zero-time");
      if (out_format == "aedat4")
      {
        dvs_driver::formats::Aedat4Writer w(output, s.width, s.height);
        writeInPieces(w, s.events, write_meter.writeCallback());
      }
      else if (out_format == "raw")
      {
        dvs_driver::formats::Evt3Writer w(output, s.width, s.height);
        writeInPieces(w, s.events, write_meter.writeCallback());
      }
      else
      {
        dvs_driver::formats::Hdf5Writer w(output, s.width, s.height);
        writeInPieces(w, s.events, write_meter.writeCallback());
      }
    }
    else if (dvs_driver::eventFileFormat(output) == dvs_driver::EventFileFormat::Bag)
    {
      if (!s.events.empty() && s.events.front().t_ns < 0)
        throw dvs_driver::EventFileError(input + ": time stamps are negative (first " +
                                         std::to_string(s.events.front().t_ns) +
                                         " ns) and a bag cannot hold them: add --zero-time");
      packets = dvs_driver::writeEventsBag(output, o.topic, s, static_cast<int64_t>(o.period_s * 1e9 + 0.5), "dvs",
                                           write_meter.writeCallback());
    }
    else
      dvs_driver::writeEventsText(output, s.events, write_meter.writeCallback());  // checked: throws WriteError
    write_meter.finish(s.events.size(), s.events.size());
    if (!o.imu.empty())
    {
      // The IMU samples, on the events' time base (shifted with them by --zero-time).
      for (dvs_driver::ImuSample& m : in.imu)
        m.t_ns += offset_ns;
      if (in.imu.empty())
        std::cerr << "convert: warning: " << input << ": no IMU samples (" << recording.format
                  << " carries none, or the camera's IMU was off): " << o.imu << " holds only its header line\n";
      dvs_driver::writeImuText(o.imu, in.imu);  // checked: throws WriteError naming the file
    }

    const double span = s.events.empty() ? 0.0 : (s.events.back().t_ns - s.events.front().t_ns) * 1e-9;
    char buf[512];
    std::snprintf(buf, sizeof(buf),
                  "{\"format\":%s,\"events\":%zu,\"span_s\":%.6f,\"width\":%u,\"height\":%u,\"sensor\":%s,\"skipped_words\":%llu,"
                  "\"truncated_bytes\":%zu,\"packets\":%zu,\"time_offset_ns\":%lld,",
                  dvs_driver::jsonString(recording.format).c_str(), s.events.size(), span, s.width, s.height,
                  dvs_driver::jsonString(in.sensor_name).c_str(),
                  static_cast<unsigned long long>(in.skipped), in.truncated_bytes, packets,
                  static_cast<long long>(offset_ns));
    std::cout << buf << "\"records\":" << a.records << ",\"skipped\":{\"sync\":" << a.sync_events
              << ",\"aps\":" << a.aps_samples << ",\"imu\":" << a.imu_samples << ",\"out_of_range\":" << a.out_of_range
              << "}," << checks.json() << ",\"imu_samples\":" << in.imu.size() << "}" << std::endl;
  }
  catch (const std::exception& e)
  {
    std::cerr << "convert: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
