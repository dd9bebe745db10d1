#pragma once
// Event Camera Dataset `events.txt`: one event a line, `t x y p`, t in seconds (decimal,
// nanosecond resolution), x y integer pixels (top-left origin), p 1 = ON, 0 = OFF.
#include <dvs_driver/event.h>
#include <dvs_driver/progress_meter.h>
#include <dvs_driver/event_source.h>

#include <fstream>

#include <iosfwd>
#include <stdexcept>
#include <string>

namespace dvs_driver
{
/// Thrown for unreadable or malformed event files; the message names file and line.
class EventFileError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// Read a whole events.txt. Blank lines and lines starting with '#' are skipped. Throws
/// EventFileError naming the file and line on a malformed line, a negative pixel coordinate,
/// a polarity other than 0/1, or a time that goes backwards.
EventVector readEventsText(const std::string& path);
EventVector readEventsText(std::istream& in, const std::string& name);
/// The same with progress reports (progress_meter.h) every 65,536 lines: events, bytes read,
/// `total_bytes`.
EventVector readEventsText(std::istream& in, const std::string& name, const ReadProgress& progress,
                           uint64_t total_bytes);

/// An events.txt read a block of lines at a time (same checks as readEventsText). The sensor size
/// is not stated in the file (info() width/height 0; see probeSource).
class TextFileSource : public EventSource
{
public:
  /// Throws EventFileError naming the file when it cannot be opened.
  explicit TextFileSource(const std::string& path);
  const EventSourceInfo& info() const override { return info_; }
  size_t read(EventVector& out, size_t max_events) override;
  void rewind() override;

private:
  std::ifstream in_;
  EventSourceInfo info_;
  std::string line_;
  size_t line_no_ = 0;
  int64_t last_t_ = INT64_MIN;
};

/// Format one event as an events.txt line (no newline), time with 9 decimals.
std::string formatEventLine(const Event& e);

/// Write events as events.txt, checked (checked_write.h): throws WriteError naming the file and
/// the OS reason when it cannot be written (missing folder, full disk, ...); the file appears
/// under its name only when complete. `progress` (optional) hears the events written so far
/// every 65,536 events.
void writeEventsText(const std::string& path, const EventVector& events, const WriteProgress& progress = {});
void writeEventsText(std::ostream& out, const EventVector& events, const WriteProgress& progress = {});

/// Parse a decimal seconds string ("12.345678901", "-0.5", "3") into integer nanoseconds
/// exactly (no floating-point rounding). Returns false when it is not a number.
bool parseSecondsToNs(const char* begin, const char* end, int64_t& ns);
}  // namespace dvs_driver
