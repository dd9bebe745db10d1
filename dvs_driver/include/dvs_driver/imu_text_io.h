#pragma once
// Event Camera Dataset `imu.txt` (reference/formats.md): one sample a line,
// `t ax ay az gx gy gz`, t in seconds (decimal, nanosecond resolution), specific force in m/s^2,
// angular velocity in rad/s, in the IMU's axes; lines starting with '#' and blank lines are
// skipped. The one place that reads and writes it (ROS-free).
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/imu_sample.h>

#include <iosfwd>
#include <string>

namespace dvs_driver
{
/// Read a whole imu.txt. Throws EventFileError naming the file and line on a malformed line
/// (not 7 fields, a field that is not a number), a non-finite value (nan, inf), or a time that
/// goes backwards (equal times are kept), as readEventsText does for events.txt.
ImuVector readImuText(const std::string& path);
ImuVector readImuText(std::istream& in, const std::string& name);

/// One imu.txt line (no newline): time with 9 decimals, the six values in the shortest decimal
/// form that reads back to the same double (exact round trip).
std::string formatImuLine(const ImuSample& s);

/// The header line writeImuText starts with by default (with its newline).
extern const char* const kImuTextHeader;

/// Write samples as imu.txt (`header` first: a `#` comment line, kImuTextHeader by default),
/// checked (checked_write.h): throws WriteError naming the file and the OS reason; the file
/// appears under its name only when complete. Throws EventFileError for a non-finite value.
void writeImuText(const std::string& path, const ImuVector& samples, const char* header = kImuTextHeader);
void writeImuText(std::ostream& out, const ImuVector& samples, const char* header = kImuTextHeader);
}  // namespace dvs_driver
