#pragma once
// AEDAT 3.1 (cAER / libcaer tools) reader and writer (ROS-free): `#` header lines (CRLF) ending in
// `#!END-HEADER`, then packets [28-byte header][events]. Polarity packets (type 1) give the
// events (valid bit honoured, timestamp overflow unwrapped); other packet types are skipped and
// counted. The sensor size comes from the `#Source` device name (DVS128, DAVIS240, DAVIS346...).
#include <dvs_driver/formats/event_format.h>

#include <cstdio>
#include <memory>
#include <string>

namespace dvs_driver
{
namespace formats
{
std::unique_ptr<EventFileReader> openAedat3(const std::string& path);

/// Sensor size of a cAER device name ("DAVIS346B" -> 346x260); false if unknown.
bool aedat3SourceSize(const std::string& device, uint32_t& width, uint32_t& height);
}  // namespace formats
}  // namespace dvs_driver
