#pragma once
// jAER AEDAT 2.0 reader (ROS-free): DVS128 files, and the DVS events and IMU samples of
// DAVIS240/346 files. Format (../shared/reference/formats.md): '#' header lines ending in CRLF,
// the first `#!AER-DAT2.0`; then 8-byte big-endian records {int32 address, int32 timestamp in us}.
//
// DAVIS IMU (jAER's IMUSample, Invensense MPU-6150): one sample is 7 consecutive records with the
// same time stamp, address (a & 0x80000C00) == 0x80000C00, bits 28-30 the value's code (0 ax,
// 1 ay, 2 az, 3 temperature, 4 gx, 5 gy, 6 gz, in this order), bits 12-27 the signed 16-bit raw
// value. Scales: accelerometer 16384 / 2^k LSB per g for a full scale of 2, 4, 8, 16 g; gyroscope
// 131 / 2^k LSB per deg/s for 250, 500, 1000, 2000 deg/s; temperature raw / 340 + 35 deg C. The
// full scales are read from the header's jAER preferences (`ImuAccelScale` = ImuAccelScaleG8,
// `ImuGyroScale` = GyroFullScaleDegPerSec1000, else the MPU registers `imu4_ACCEL_CONFIG` /
// `imu3_GYRO_CONFIG`, bits 3-4); without them jAER's defaults, 4 g and 500 deg/s (reported in
// AedatInfo::imu_scale_from_header). Values are in the IMU chip's axes as recorded (no sign
// flips; rpg_dvs_ros maps a DAVIS's IMU to its camera frame as (-x, y, -z) for both sensors).
#include <dvs_driver/event.h>
#include <dvs_driver/event_source.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/imu_sample.h>

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
  uint64_t imu_samples = 0;     ///< DAVIS IMU records (7 per IMU sample), not events
  uint64_t imu_decoded = 0;     ///< complete IMU samples decoded (AedatRecording::imu, takeImu)
  uint64_t imu_dropped = 0;     ///< IMU records of incomplete or disordered samples, or of
                                ///< samples whose time goes backwards, dropped
  double imu_accel_full_scale_g = 4;        ///< accelerometer full scale used (g)
  double imu_gyro_full_scale_deg_s = 500;   ///< gyroscope full scale used (deg/s)
  bool imu_scale_from_header = false;       ///< the full scales come from the header (else defaults)
  bool imu_accel_scale_named = false;       ///< header: `ImuAccelScale` (preferred to the register)
  bool imu_gyro_scale_named = false;        ///< header: `ImuGyroScale` (preferred to the register)
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
  ImuVector imu;       ///< DAVIS IMU samples (same time base), empty for DVS128 files
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
  /// Move the IMU samples decoded by read() so far (in file order) to the end of `out`; returns
  /// how many. Call after read() to keep memory bounded: at most 1,048,576 are kept between
  /// calls, further ones are counted in aedatInfo().imu_dropped.
  size_t takeImu(ImuVector& out);

private:
  std::ifstream in_;
  EventSourceInfo info_;
  AedatInfo aedat_;
  std::unique_ptr<AedatRecordDecoder> decoder_;
  std::vector<uint8_t> bytes_;
  ImuVector imu_;
  uint64_t next_record_ = 0;
};

/// Byte offset where the records start (after the last header line). A header line starts with
/// '#', holds only text and ends in '\n'; `#End Of ASCII Header` ends the header explicitly, so a
/// first data byte that happens to be '#' is not taken for a header line.
size_t findAedatDataOffset(const uint8_t* data, size_t size);
}  // namespace dvs_driver
