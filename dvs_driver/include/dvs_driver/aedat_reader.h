#pragma once
// jAER AEDAT 2.0 reader (ROS-free): DVS128 files and the DVS events of DAVIS240/346 files.
// Format (../shared/reference/formats.md): '#' header lines ending in CRLF, the first
// `#!AER-DAT2.0`; then 8-byte big-endian records {int32 address, int32 timestamp in us}.
#include <dvs_driver/event.h>
#include <dvs_driver/event_source.h>
#include <dvs_driver/event_text_io.h>

#include <fstream>
#include <memory>
#include <vector>

#include <cstdint>
#include <string>

namespace dvs_driver
{
/// Thrown for unreadable or malformed AEDAT files; the message names the file and the problem.
class AedatError : public EventFileError
{
public:
  using EventFileError::EventFileError;
};

enum class AedatSensor
{
  DVS128,
  DAVIS240,
  DAVIS346
};

/// What was found in an AEDAT file besides the DVS events.
struct AedatInfo
{
  AedatSensor sensor = AedatSensor::DVS128;
  std::string sensor_name;      ///< "DVS128", "DAVIS240" or "DAVIS346"
  std::string ae_chip;          ///< the header's `# AEChip:` value ("" when absent)
  size_t data_offset = 0;       ///< byte where the records start
  uint64_t records = 0;         ///< complete 8-byte records
  uint64_t dvs_events = 0;      ///< pixel events returned
  uint64_t sync_events = 0;     ///< external/special events (skipped)
  uint64_t aps_samples = 0;     ///< DAVIS frame samples (skipped)
  uint64_t imu_samples = 0;     ///< DAVIS IMU samples (skipped)
  uint64_t out_of_range = 0;    ///< records whose pixel lies outside the sensor (skipped)
  uint64_t non_monotonic = 0;   ///< events whose time went backwards (kept, time clamped)
  uint64_t timestamp_wraps = 0; ///< int32 time stamp overflows unwrapped into 64 bits
  size_t truncated_bytes = 0;   ///< bytes of an incomplete last record (0 = not truncated)
  /// What the reader repaired or dropped (event_validation.h): steps back in the file's times
  /// before clamping (backwards, max_backwards_ns), clamped (= non_monotonic), outside_sensor
  /// (= out_of_range). Duplicates among the events returned are for the consumer's validator.
  EventChecks checks;
  /// Records not returned as events.
  uint64_t skippedRecords() const { return sync_events + aps_samples + imu_samples + out_of_range; }
};

struct AedatRecording
{
  EventStream stream;  ///< DVS events, t_ns = file microseconds * 1000 (may be negative)
  AedatInfo info;
};

/// Read a whole AEDAT 2.0 file. Throws AedatError when the file is missing, is not AEDAT, has
/// another version, or the sensor cannot be determined. A truncated last record is tolerated and
/// reported in info.truncated_bytes; a header-only file gives zero events.
AedatRecording readAedat(const std::string& path);
/// Same, from bytes in memory (`name` is used in messages).
AedatRecording readAedat(const uint8_t* data, size_t size, const std::string& name);

struct AedatRecordDecoder;

/// An AEDAT 2.0 file read a block of records at a time (same decoding as readAedat; memory bounded
/// by the block). The constructor reads the header (and, only when the header does not name the
/// sensor, checks every address in pieces); throws AedatError like readAedat.
class AedatFileSource : public EventSource
{
public:
  explicit AedatFileSource(const std::string& path);
  ~AedatFileSource() override;
  const EventSourceInfo& info() const override { return info_; }
  size_t read(EventVector& out, size_t max_events) override;
  void rewind() override;
  /// Header facts and the counts of the records read so far (since the last rewind).
  const AedatInfo& aedatInfo() const { return aedat_; }
  /// aedatInfo().checks.
  EventChecks checks() const override { return aedat_.checks; }

private:
  std::ifstream in_;
  EventSourceInfo info_;
  AedatInfo aedat_;
  std::unique_ptr<AedatRecordDecoder> decoder_;
  std::vector<uint8_t> bytes_;
  uint64_t next_record_ = 0;
};

/// Byte offset where the records start (after the last header line). A header line starts with
/// '#', holds only text and ends in '\n'; `#End Of ASCII Header` ends the header explicitly, so a
/// first data byte that happens to be '#' is not taken for a header line.
size_t findAedatDataOffset(const uint8_t* data, size_t size);
}  // namespace dvs_driver
