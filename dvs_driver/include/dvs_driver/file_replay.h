#pragma once
// A recording as an EventInput (ROS-free): streams an EventSource (any file format, or events in
// memory) and replays it in real time, scaled by a speed factor, or as fast as possible.
//
// Two threads: the reader pulls blocks from the source into a queue bounded to
// `queue_events` events (memory stays bounded whatever the file size; the reader waits while the
// queue is full), shifting the times of every further loop; the player takes the events in order,
// hands them to the listener in chunks of at most `chunk_period_ns` / `chunk_max_events`, and
// waits until each chunk's last event is due. Both stop (and are joined) in stop() or on
// destruction, wherever they are in the file.
#include <dvs_driver/event_input.h>
#include <dvs_driver/event_source.h>
#include <dvs_driver/event_validation.h>

#include <chrono>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

namespace dvs_driver
{
struct FileReplayOptions
{
  double speed = 1.0;               ///< 1 = real time, 2 = twice as fast, 0 = as fast as possible
  int64_t chunk_period_ns = 100000; ///< events are handed over in chunks of at most this much time
  size_t chunk_max_events = 4096;
  bool loop = false;                ///< start again at the end (times keep increasing: +span +1 ms)
  size_t read_block = 4096;         ///< events read from the source at a time
  size_t queue_events = 262144;     ///< at most this many events read ahead (4 MiB)
  /// Sensor size: events outside it are dropped and counted (checks()). 0 x 0 = the source's
  /// size (a source that does not state one: no outside check).
  uint32_t sensor_width = 0, sensor_height = 0;
};

class FileReplay : public EventInput
{
public:
  /// The source must deliver events in time order. Throws std::invalid_argument on bad options.
  FileReplay(std::unique_ptr<EventSource> source, const FileReplayOptions& options);
  ~FileReplay() override;
  /// Starts the reader and the player; returns at once. The listener gets onEvents chunks, then
  /// onEndOfInput (played once to its end), or onInputError (the file turned out malformed part
  /// way through; what came before it was delivered).
  void start(EventInputListener& listener) override;
  void stop() override;
  std::string description() const override { return source_->info().name; }
  const EventSourceInfo& info() const { return source_->info(); }
  /// Events delivered so far.
  uint64_t delivered() const { return delivered_; }
  /// Most events ever waiting in the queue (<= queue_events + read_block).
  size_t maxQueued() const { return max_queued_; }
  /// The validation of the events played so far (event_validation.h): events outside the
  /// sensor (dropped), time stamps going backwards, exact duplicates (both kept), plus what the
  /// source repaired or dropped itself (EventSource::checks(), e.g. AEDAT's clamped times), over
  /// every loop. While not clean(), the listener gets onWarning with the summary: at the first
  /// problem, then at most every 5 s while the counts grow, and at the end.
  EventChecks checks() const;

private:
  struct Block
  {
    EventVector events;
    bool end = false;
    std::string error;  ///< not empty: the reader failed with this message
    EventChecks checks; ///< the validation up to and including this block
  };
  void readLoop();
  void playLoop(EventInputListener& listener);
  void deliver(EventInputListener& listener, EventVector& chunk);
  void reportChecks(EventInputListener& listener, const EventChecks& checks, bool last);
  EventChecks currentChecks() const;  // reader thread
  bool push(Block block);
  bool pop(Block& block);

  std::unique_ptr<EventSource> source_;
  FileReplayOptions options_;
  std::thread reader_, player_;
  std::atomic<bool> stopping_{false};
  std::atomic<uint64_t> delivered_{0};
  std::atomic<size_t> max_queued_{0};

  mutable std::mutex mutex_;          // the queue, the pool, played_checks_
  std::condition_variable changed_;   // queue changed, or stopping
  std::deque<Block> queue_;
  size_t queued_events_ = 0;
  std::vector<EventVector> pool_;     // emptied blocks for the reader to reuse

  // Validation: the reader's validator and the source's counts of earlier loops (reader thread);
  // the counts of what was played (mutex_).
  EventValidator validator_;
  EventChecks earlier_passes_;
  EventChecks played_checks_;

  // Player state (player thread only).
  bool started_clock_ = false;
  std::chrono::steady_clock::time_point wall0_;
  int64_t t0_ = 0;
  EventChecks reported_;
  std::chrono::steady_clock::time_point last_report_;
};
}  // namespace dvs_driver
