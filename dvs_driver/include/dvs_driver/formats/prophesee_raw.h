#pragma once
// Prophesee RAW files (Metavision / OpenEB): `% key value` header lines, then EVT 2.0 or EVT 3.0
// words. The sensor size comes from `format` (EVT3;height=720;width=1280), else `geometry`
// (1280x720), else the system_ID (21 -> 640x480, 48/49/50 -> 1280x720), else unknown (0).
#include <dvs_driver/formats/event_format.h>

#include <cstdio>
#include <map>
#include <vector>
#include <memory>
#include <string>

namespace dvs_driver
{
namespace formats
{
struct RawHeader
{
  std::map<std::string, std::string> keys;  ///< every `% key value` line
  size_t data_offset = 0;                   ///< first data byte
  int evt = 0;                              ///< 2 or 3 (EVT 2.1 and others are rejected)
  uint32_t width = 0, height = 0;
  std::string size_source;                  ///< "format", "geometry", "system_ID 48" or ""
  int64_t time_offset_us = 0;               ///< `% dvs_time_offset_us` (written by Evt3Writer)
};

/// Parse the header at the start of `data` (the whole header must be inside). Throws
/// EventFormatError naming `name` for a missing/unsupported EVT version or big-endian data.
RawHeader parseRawHeader(const uint8_t* data, size_t size, const std::string& name);

/// Sensor size known for a Prophesee system id (false if unknown).
bool rawSystemIdSize(long system_id, uint32_t& width, uint32_t& height);

/// Streaming reader of a RAW file (EVT 2.0 or 3.0, from the header).
std::unique_ptr<EventFileReader> openPropheseeRaw(const std::string& path);

/// Writes an EVT 3.0 RAW file (`% evt 3.0`, `% format EVT3;height=H;width=W`, `% geometry WxH`).
/// Times are stored in microseconds (t_ns / 1000, floor). A file whose first event lies beyond
/// 2^32 us (e.g. Unix-epoch times from AEDAT 4.0) gets the whole seconds before it as
/// `% dvs_time_offset_us N`, which the reader adds back (other tools ignore the key and see times
/// from near 0). Events may step back in time by less than 2048 x 4096 us within one 2^24 us loop.
class Evt3Writer
{
public:
  /// Throws EventFormatError if the file cannot be created or the size exceeds 2048x2048.
  Evt3Writer(const std::string& path, uint32_t width, uint32_t height);
  ~Evt3Writer();  ///< closes (errors then are swallowed: call close() to see them)
  /// Throws EventFormatError for an event outside the sensor, before the time origin, or
  /// too far back in time (see above).
  void write(const Event* events, size_t n);
  void write(const EventVector& events) { write(events.data(), events.size()); }
  void close();

private:
  void start(int64_t first_us);
  void flush();

  std::string path_;
  std::FILE* f_ = nullptr;
  uint32_t width_, height_;
  bool started_ = false;
  int64_t offset_us_ = 0;
  int64_t total_th_ = -1;  // emitted loop * 4096 + time high
  int32_t tl_ = -1, y_ = -1;
  uint64_t written_ = 0;
  std::vector<uint16_t> words_;
};
}  // namespace formats
}  // namespace dvs_driver
