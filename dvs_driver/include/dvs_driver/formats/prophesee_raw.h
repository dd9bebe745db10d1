#pragma once
// Prophesee RAW files (Metavision / OpenEB): `% key value` header lines, then EVT 2.0 or EVT 3.0
// words. The sensor size comes from `format` (EVT3;height=720;width=1280), else `geometry`
// (1280x720), else the system_ID (21 -> 640x480, 48/49/50 -> 1280x720), else unknown (0).
#include <dvs_driver/formats/event_format.h>

#include <map>
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
};

/// Parse the header at the start of `data` (the whole header must be inside). Throws
/// EventFormatError naming `name` for a missing/unsupported EVT version or big-endian data.
RawHeader parseRawHeader(const uint8_t* data, size_t size, const std::string& name);

/// Sensor size known for a Prophesee system id (false if unknown).
bool rawSystemIdSize(long system_id, uint32_t& width, uint32_t& height);

/// Streaming reader of a RAW file (EVT 2.0 or 3.0, from the header).
std::unique_ptr<EventFileReader> openPropheseeRaw(const std::string& path);
}  // namespace formats
}  // namespace dvs_driver
