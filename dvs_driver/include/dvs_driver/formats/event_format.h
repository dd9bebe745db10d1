#pragma once
// Common interface of the streaming event-file readers (ROS-free): format detection from the
// file's first bytes (never its extension), one reader interface, statistics about damage.
// Layouts: ../shared/reference/event-formats.md; the readers are in formats/*.h.
#include <dvs_driver/event.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/imu_sample.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dvs_driver
{
/// Thrown for a file that cannot be read as a supported event format: missing file, unknown
/// format, unsupported version, compression or encoding (the message names the file and it).
class EventFormatError : public EventFileError
{
public:
  using EventFileError::EventFileError;
};

/// What the first bytes of a file say it is.
enum class EventFormat
{
  Unknown,
  Aedat2,     ///< `#!AER-DAT2.0` (read by aedat_reader.h)
  Aedat3,     ///< `#!AER-DAT3.x`
  Aedat4,     ///< `#!AER-DAT4.0`
  PropheseeRaw,  ///< `% ` header lines (EVT 2.0 / 3.0 chosen by the header)
  RosBag1,       ///< `#ROSBAG V2.0` (read by event_bag_io.h, not by openEventFileReader)
  Hdf5,          ///< HDF5 signature (DSEC / flat layouts: formats/hdf5_events.h)
  Sqlite         ///< `SQLite format 3` (e.g. a ROS 2 bag; not read)
};

/// Detect the format from the first bytes of the file (throws EventFormatError if unreadable).
/// Unknown for anything else, e.g. events.txt.
EventFormat detectEventFormat(const std::string& path);
/// Same, from the first bytes of a file (at least 16 for a sure answer).
EventFormat detectEventFormat(const uint8_t* data, size_t size);
const char* eventFormatName(EventFormat f);

/// One external trigger (EVT 2.0/3.0 EXT_TRIGGER words).
struct TriggerEvent
{
  int64_t t_ns = 0;
  uint8_t channel = 0;  ///< trigger channel id
  bool edge = false;    ///< true = rising
};

inline bool operator==(const TriggerEvent& a, const TriggerEvent& b)
{
  return a.t_ns == b.t_ns && a.channel == b.channel && a.edge == b.edge;
}

/// What a reader met besides the events it delivered. Counters only grow.
struct ReaderStats
{
  uint64_t events = 0;             ///< events delivered so far
  uint64_t bytes_read = 0;         ///< file bytes consumed so far (for progress)
  uint64_t file_size = 0;          ///< size of the file in bytes
  uint64_t unknown_words = 0;      ///< unknown or reserved words / packet types skipped
  uint64_t other_words = 0;        ///< known words/packets that carry no CD event (monitoring, IMU,
                                   ///< frames, continued words, other streams), skipped
  uint64_t out_of_range = 0;       ///< events outside the sensor size, dropped
  uint64_t before_time = 0;        ///< events before the first time reference, dropped
  uint64_t triggers = 0;           ///< external trigger events seen
  uint64_t imu_samples = 0;        ///< IMU samples decoded (see takeImu)
  uint64_t time_wraps = 0;         ///< time counter wraps unwrapped (EVT 3.0: 2^24 us; EVT 2.0: 2^34 us)
  uint64_t time_backsteps = 0;     ///< time steps backwards taken as they are (EVT 3.0 TIME_LOW/HIGH)
  uint64_t invalid_events = 0;     ///< events the file marks invalid (AEDAT 3.1 valid bit), skipped
  uint64_t damaged_packets = 0;    ///< packets that could not be decoded (bad compression, layout), skipped
  bool truncated = false;          ///< the file ends inside a word, packet or record
  uint64_t truncated_offset = 0;   ///< byte offset where the incomplete data starts
  uint64_t truncated_bytes = 0;    ///< bytes of that incomplete data
  std::vector<std::string> warnings;  ///< human-readable, each at most once per kind
};

/// Streaming reader of one event file. Memory is bounded whatever the file size: the file is
/// read in chunks. Times are the file's own (t_ns = microseconds x 1000 for all formats here).
class EventFileReader
{
public:
  virtual ~EventFileReader();

  /// Append up to max_events events (in file order) to `out`. Returns false once the file is
  /// exhausted and nothing was appended; may append fewer than max_events before the end.
  /// Throws EventFormatError only for errors that make the rest of the file unreadable.
  virtual bool read(EventVector& out, size_t max_events) = 0;

  /// Sensor size from the file (0 when the file does not say).
  virtual uint32_t width() const = 0;
  virtual uint32_t height() const = 0;
  /// e.g. "Prophesee RAW EVT 3.0", "AEDAT 4.0 (LZ4)".
  virtual std::string formatName() const = 0;
  virtual ReaderStats stats() const = 0;

  /// Move the external triggers decoded so far (in file order) to the end of `out`; returns how
  /// many. Call after read() to keep memory bounded (at most 1,048,576 are kept between calls;
  /// further ones are counted in stats().triggers only).
  virtual size_t takeTriggers(std::vector<TriggerEvent>& out);

  /// Move the IMU samples decoded so far (in file order; imu_sample.h: SI units, the IMU's own
  /// axes) to the end of `out`; returns how many. Same bounds as takeTriggers. Formats without
  /// IMU data return 0. AEDAT 4.0: the first IMUS stream (file: g and deg/s); AEDAT 2.0: the
  /// DAVIS IMU6 records (aedat_reader.h).
  virtual size_t takeImu(std::vector<ImuSample>& out);

  /// Total number of events the file announces (AEDAT 4.0 data table), -1 when unknown.
  virtual int64_t expectedEvents() const { return -1; }

  /// Read everything that is left (convenience for tests and small files).
  EventVector readAll();
};

/// Open `path`, detect its format from its first bytes and return the matching streaming reader
/// (Prophesee RAW EVT 2.0/3.0, AEDAT 3.1, AEDAT 4.0; AEDAT 2.0 through aedat_reader.h, which
/// reads the whole file first). Throws EventFormatError naming the file and the problem (unknown
/// format, a detected format this function does not read, unsupported version / compression,
/// bad header). Text files (events.txt) have no signature: they come back as unknown.
std::unique_ptr<EventFileReader> openEventFileReader(const std::string& path);
}  // namespace dvs_driver
