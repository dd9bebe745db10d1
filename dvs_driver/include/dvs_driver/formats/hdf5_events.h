#pragma once
// HDF5 event files (ROS-free, libhdf5 C API): a streaming reader of two layouts and a writer.
//  - DSEC layout: /events/x uint16, /events/y uint16, /events/p uint8 (0/1), /events/t uint32
//    (microseconds relative to /t_offset), /t_offset int64 scalar (us; absolute = t + t_offset,
//    0 when absent), /ms_to_idx uint64 (ms_to_idx[k] = index of the first event with
//    t >= 1000 k). Sensor size 640x480 unless uint attributes `width`/`height` (root or /events)
//    say otherwise.
//  - flat layout: /x, /y, /t (microseconds), /p at the root; size from root attributes
//    `width`/`height`, else unknown (0).
// Any integer dataset type is accepted (converted by libhdf5); p > 0 = ON. Datasets may be
// chunked and compressed (gzip, or blosc = filter 32001 through Debian's
// hdf5-filter-plugin-blosc-serial, found in libhdf5's default plugin directory or
// HDF5_PLUGIN_PATH). Layouts: ../shared/reference/event-formats.md section 5.
#include <dvs_driver/formats/event_format.h>

#include <memory>
#include <string>

namespace dvs_driver
{
namespace formats
{
/// Open an HDF5 event file (layout detected from its datasets). The reader reads each dataset
/// in hyperslabs of at most 65,536 events, so memory stays bounded. Throws EventFormatError
/// naming the problem: not HDF5 / truncated or corrupt, unsupported layout (lists what the root
/// holds; Prophesee's ECF-coded /CD/events is named), datasets of different lengths or
/// non-integer types, a compression filter that is not available.
std::unique_ptr<EventFileReader> openHdf5Events(const std::string& path);

enum class Hdf5Layout
{
  Flat,  ///< /x, /y, /t (int64 us), /p (uint8) at the root
  Dsec   ///< /events/{x,y,t,p}, /t_offset, /ms_to_idx
};

enum class Hdf5Compression
{
  None,
  Gzip,  ///< deflate, level 1-9
  Blosc  ///< filter 32001 (blosc zstd + shuffle), level 1-9; needs the blosc plugin
};

struct Hdf5WriterOptions
{
  Hdf5Layout layout = Hdf5Layout::Flat;
  Hdf5Compression compression = Hdf5Compression::None;
  int level = 4;
  size_t chunk_events = 65536;  ///< HDF5 chunk size (events) and write buffer size
};

/// Writes events to an HDF5 file readable by openHdf5Events and by h5py. Times are written in
/// microseconds (t_ns / 1000, rounded down). DSEC: t_offset = the first event's time; events
/// must not go back before it and t - t_offset must fit in uint32 (~71 min), else
/// EventFormatError. Both layouts store root attributes `width` and `height` (uint32). Events
/// are buffered (chunk_events) and appended to extendible datasets; close() writes the rest,
/// /t_offset and /ms_to_idx (DSEC). Throws EventFormatError on I/O errors, a missing blosc
/// plugin, or coordinates beyond 65535.
class Hdf5Writer
{
public:
  Hdf5Writer(const std::string& path, uint32_t width, uint32_t height, Hdf5WriterOptions options = {});
  ~Hdf5Writer();  ///< closes quietly
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  void write(const Event* events, size_t n);
  void write(const EventVector& events) { write(events.data(), events.size()); }
  void close();
  uint64_t eventsWritten() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
}  // namespace formats
}  // namespace dvs_driver
