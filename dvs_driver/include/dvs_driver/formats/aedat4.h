#pragma once
// AEDAT 4.0 (iniVation DV) reader and writer (ROS-free). The IOHeader, packet and data-table
// flatbuffers are read and written by hand (no flatc). Compression: none, LZ4 frame (LZ4 and
// LZ4_HIGH), zstd (ZSTD and ZSTD_HIGH). The events are those of the first EVTS stream; the
// samples of the first IMUS stream come out through takeImu(); other streams (frames, triggers)
// are skipped. Every non-EVTS packet is counted in other_words.
#include <dvs_driver/formats/event_format.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace dvs_driver
{
namespace formats
{
enum class Aedat4Compression : int32_t
{
  None = 0,
  Lz4 = 1,
  Lz4High = 2,
  Zstd = 3,
  ZstdHigh = 4
};
const char* aedat4CompressionName(Aedat4Compression c);

/// Streaming AEDAT 4.0 reader. With a data table (the normal case) the EVTS packets are visited
/// through it; without one (interrupted recording) or with a damaged one, the packets are scanned
/// to the end of the file and a truncated last packet is reported in stats().
std::unique_ptr<EventFileReader> openAedat4(const std::string& path);

struct Aedat4WriterOptions
{
  Aedat4Compression compression = Aedat4Compression::Lz4;
  size_t events_per_packet = 10000;
  std::string source = "DVS_SUITE";  ///< the stream info's `source` (camera name)
};

/// Writes one EVTS stream (id 0) of the given size, then the data table on close().
class Aedat4Writer
{
public:
  /// Throws EventFormatError if the file cannot be created.
  Aedat4Writer(const std::string& path, uint32_t width, uint32_t height, const Aedat4WriterOptions& options = {});
  ~Aedat4Writer();  ///< closes (errors then are swallowed: call close() to see them)
  /// t is stored in microseconds (t_ns / 1000, floor); events are written in the order given
  /// (each data-table entry records its packet's smallest and largest time).
  void write(const EventVector& events);
  void write(const Event* events, size_t n);
  /// Flush the last packet, write the data table, patch the header. Throws on I/O errors.
  void close();

private:
  void flushPacket();
  void writeCompressed(int32_t stream_id, const std::vector<uint8_t>& raw, bool with_header);

  std::string path_;
  std::FILE* f_ = nullptr;
  uint32_t width_, height_;
  Aedat4WriterOptions opt_;
  std::vector<Event> packet_;
  struct TableEntry
  {
    int64_t byte_offset, elements, t_start, t_end;
    int32_t size;
  };
  std::vector<TableEntry> table_;
  std::vector<uint8_t> raw_, compressed_;
  uint64_t offset_ = 0;
  uint64_t table_pos_field_ = 0;  // file offset of the dataTablePosition int64
  int64_t last_t_us_ = INT64_MIN;
};
}  // namespace formats
}  // namespace dvs_driver
