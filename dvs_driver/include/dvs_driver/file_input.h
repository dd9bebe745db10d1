#pragma once
// A recording as an EventInput (ROS-free): replays an EventStream in real time, scaled by a
// speed factor, or as fast as possible, in chunks on its own thread.
#include <dvs_driver/event_input.h>

#include <atomic>
#include <thread>

namespace dvs_driver
{
struct FileInputOptions
{
  double speed = 1.0;              ///< 1 = real time, 2 = twice as fast, 0 = as fast as possible
  int64_t chunk_period_ns = 100000;///< events are handed over in chunks of at most this much time
  size_t chunk_max_events = 4096;
  bool loop = false;               ///< start again at the end (times keep increasing)
};

class FileInput : public EventInput
{
public:
  /// `stream` must be sorted by time. `name` is used in description().
  FileInput(EventStream stream, const std::string& name, const FileInputOptions& options);
  ~FileInput() override;
  void start(EventInputListener& listener) override;
  void stop() override;
  std::string description() const override { return name_; }
  const EventStream& stream() const { return stream_; }
  /// Events delivered so far.
  uint64_t delivered() const { return delivered_; }

private:
  void run(EventInputListener& listener);
  EventStream stream_;
  std::string name_;
  FileInputOptions options_;
  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::atomic<uint64_t> delivered_{0};
};
}  // namespace dvs_driver
