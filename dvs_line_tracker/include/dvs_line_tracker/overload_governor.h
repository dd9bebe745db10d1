#pragma once
// Keeps the live tracker from falling behind (issue 16): when event packets queue up faster than
// the tracker processes them, it first solves the pose once per `batch_solve_every` events (every
// event still attributed and buffered; 1.8x faster, BENCHMARKS.md), and when that is not enough
// also tracks only every k-th event (k, the stride, chosen per packet so that the queue would be
// worked off within `max_latency`), instead of letting the queue, the latency and the memory
// grow. ROS-free; TrackerRos asks it before each packet and tells it after. Every skipped event
// is counted (diagnostics), none silently.
#include <cstddef>
#include <cstdint>

namespace dvs_line_tracker
{
struct OverloadParams
{
  double max_latency_s = 0.05;         ///< the queue is worked off within this (0: never degrade)
  int batch_solve_every = 1;           ///< behind: the pose solved once per this many events first (1: off; 4 measured worse live, BENCHMARKS.md)
  int max_stride = 64;                 ///< at most every 64th event tracked
  size_t max_queued_events = 4000000;  ///< beyond, the oldest packets are dropped (counted)
};

/// How the next packet is tracked.
struct OverloadAction
{
  int solve_every = 1;  ///< the pose solved once per this many attributed events
  int stride = 1;       ///< every stride-th event tracked
};

struct OverloadStats
{
  uint64_t events_skipped = 0;   ///< not tracked because of a stride > 1
  uint64_t packets_batched = 0;  ///< packets tracked with the batched solve
  uint64_t packets_strided = 0;  ///< packets tracked with a stride > 1
  uint64_t packets_dropped = 0;  ///< dropped unprocessed: the queue exceeded max_queued_events
  uint64_t events_dropped = 0;
  OverloadAction last;
  int max_stride_used = 1;
};

class OverloadGovernor
{
public:
  explicit OverloadGovernor(const OverloadParams& params = OverloadParams()) : params_(params) {}

  /// How to track the next packet: `queued_events` are waiting, the next packet's included.
  /// Behind (the queue would take longer than max_latency at the measured cost) it switches to
  /// the batched solve, and adds a stride when that is not enough; it returns to every event's
  /// own solve once the queue would take less than a quarter of max_latency.
  OverloadAction actionFor(size_t queued_events);
  /// After a packet: `tracked` events went through the tracker in `seconds` (wall time).
  void tracked(size_t tracked, double seconds);
  /// Count the events a stride left out.
  void skipped(size_t events) { stats_.events_skipped += events; }
  /// Count a packet dropped unprocessed (queue over max_queued_events).
  void dropped(size_t events)
  {
    ++stats_.packets_dropped;
    stats_.events_dropped += events;
  }
  bool overQueueLimit(size_t queued_events) const { return queued_events > params_.max_queued_events; }
  /// Wall seconds per tracked event in the current mode (running mean; 0 before the first).
  double secondsPerEvent() const { return seconds_per_event_; }
  bool batched() const { return batched_; }
  const OverloadStats& stats() const { return stats_; }
  const OverloadParams& params() const { return params_; }

private:
  OverloadParams params_;
  OverloadStats stats_;
  double seconds_per_event_ = 0;
  bool batched_ = false;
};
}  // namespace dvs_line_tracker
