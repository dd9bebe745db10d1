#pragma once
// Progress of long file reads and offline runs on a terminal (ROS-free): one line on stderr,
// rewritten in place ("\r"), at most a few times per second, and nothing at all when stderr is not
// a terminal (piped, redirected to a file, under a test), so logs and scripts stay clean.
//
//   dvs_driver::ProgressMeter meter("convert", file_bytes);   // enabled when isatty(stderr)
//   for (...) meter.update(events, bytes_done);               // cheap: a clock read per call
//   meter.finish(events, bytes_done);                         // last line + newline, if any was shown
//
// The line: "convert: 12,345,678 events, 42.0 % of 512.0 MB, 31.2 M events/s"; while writing
// (setTotalEvents): "convert: writing out.aedat4: 5,000,000 events, 42.0 % of 11,904,762 events, ...".
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>

namespace dvs_driver
{
/// Progress of a read: events so far, bytes of the file consumed so far and the file's size
/// (0 = unknown: no percentage). Called by readRecording (recording.h) between batches.
using ReadProgress = std::function<void(uint64_t events, uint64_t bytes_done, uint64_t bytes_total)>;
/// Progress of a write: events written so far. Called by the writers (writeEventsText,
/// writeEventsBag) every ~65,536 events.
using WriteProgress = std::function<void(uint64_t events_written)>;
/// What a progress line's total counts: the file's bytes (reading) or the events (writing).
enum class ProgressTotal
{
  Bytes,
  Events
};

/// The progress line without control characters: "<label>: <events> events[, <p> % of <size>],
/// <rate> events/s" (events with thousands separators; size in kB/MB/GB; rate in k/M events/s;
/// the percentage only when total_bytes > 0, clamped to 100). With ProgressTotal::Events the
/// done/total pair counts events: "<p> % of <total> events".
std::string formatProgress(const std::string& label, uint64_t events, uint64_t bytes_done, uint64_t total_bytes,
                           double seconds, ProgressTotal unit = ProgressTotal::Bytes);

/// True when stderr is a terminal (isatty).
bool stderrIsTerminal();

class ProgressMeter
{
public:
  /// `enabled` false: update() and finish() print nothing. `out` = where to print (stderr).
  ProgressMeter(std::string label, uint64_t total_bytes, bool enabled = stderrIsTerminal(),
                double min_interval_s = 0.25, std::FILE* out = stderr);
  void setTotalBytes(uint64_t total_bytes)
  {
    total_ = total_bytes;
    unit_ = ProgressTotal::Bytes;
  }
  /// For a write: the percentage is of `total_events` (update(events, events)).
  void setTotalEvents(uint64_t total_events)
  {
    total_ = total_events;
    unit_ = ProgressTotal::Events;
  }
  /// Prints when at least min_interval_s passed since the last line (no allocation otherwise).
  void update(uint64_t events, uint64_t bytes_done);
  /// The final figures and a newline, when a line was printed before (a short run prints nothing).
  void finish(uint64_t events, uint64_t bytes_done);
  /// As a ReadProgress callback (total from the reader when it knows it).
  ReadProgress callback();
  /// As a WriteProgress callback (call setTotalEvents first for a percentage).
  WriteProgress writeCallback();
  bool enabled() const { return enabled_; }
  unsigned linesPrinted() const { return lines_; }

private:
  void print(uint64_t events, uint64_t bytes_done, bool last);
  std::string label_;
  uint64_t total_;
  ProgressTotal unit_ = ProgressTotal::Bytes;
  bool enabled_;
  double interval_;
  std::FILE* out_;
  double start_, last_;
  unsigned lines_ = 0;
};
}  // namespace dvs_driver
