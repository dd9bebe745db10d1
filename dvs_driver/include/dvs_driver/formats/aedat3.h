#pragma once
// AEDAT 3.1 (cAER / libcaer tools) reader and writer (ROS-free): `#` header lines (CRLF) ending in
// `#!END-HEADER`, then packets [28-byte header][events]. Polarity packets (type 1) give the
// events (valid bit honoured, timestamp overflow unwrapped); other packet types are skipped and
// counted. The sensor size comes from the `#Source` device name (DVS128, DAVIS240, DAVIS346...).
#include <dvs_driver/formats/event_format.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace dvs_driver
{
namespace formats
{
std::unique_ptr<EventFileReader> openAedat3(const std::string& path);

/// Sensor size of a cAER device name ("DAVIS346B" -> 346x260); false if unknown.
bool aedat3SourceSize(const std::string& device, uint32_t& width, uint32_t& height);

/// Writes AEDAT 3.1 polarity packets (source id 1, `#Source 1: <device>`). The device name is
/// what carries the sensor size (DVS128, DAVIS240C, DAVIS346B...). Times in microseconds
/// (t_ns / 1000, floor), >= 0; a new packet starts when the 31-bit timestamp overflows.
class Aedat3Writer
{
public:
  Aedat3Writer(const std::string& path, const std::string& device, size_t events_per_packet = 4096);
  ~Aedat3Writer();
  void write(const Event* events, size_t n);
  void write(const EventVector& events) { write(events.data(), events.size()); }
  void close();

private:
  void flushPacket();
  std::string path_;
  std::FILE* f_ = nullptr;
  size_t per_packet_;
  int32_t overflow_ = -1;
  std::vector<uint32_t> words_;  // data, timestamp pairs
};
}  // namespace formats
}  // namespace dvs_driver
