#pragma once
// Keeps the live tracker from falling behind (issue 16): when event packets queue up faster than
// the tracker processes them, it tracks every k-th event (k, the stride, chosen per packet so
// that the queue would be worked off within `max_latency`) instead of letting the queue, the
// latency and the memory grow; while the tracker initialises, every k-th packet whole instead
// (skipWholePacket). ROS-free; TrackerRos asks it before each packet and tells it
// after. Every skipped event is counted (diagnostics), none silently. (Solving the pose once per
// few events before striding was measured worse live: BENCHMARKS.md.)
#include <cstddef>
#include <cstdint>

namespace dvs_line_tracker
{
struct OverloadParams
{
  double max_latency_s = 0.1;          ///< the queue is worked off within this (0: never skip)
  int max_stride = 64;                 ///< at most every 64th event tracked
  size_t max_queued_events = 4000000;  ///< beyond, the oldest packets are dropped (counted)
};

struct OverloadStats
{
  uint64_t events_skipped = 0;   ///< not tracked because of a stride > 1
  uint64_t packets_strided = 0;  ///< packets tracked with a stride > 1
  uint64_t packets_skipped = 0;  ///< skipped whole while initialising (their events are in events_skipped)
  uint64_t events_skipped_whole = 0;  ///< the events of those packets (no pose, no latency counted)
  uint64_t packets_dropped = 0;  ///< dropped unprocessed: the queue exceeded max_queued_events
  uint64_t events_dropped = 0;
  int last_stride = 1;
  int max_stride_used = 1;
};

class OverloadGovernor
{
public:
  explicit OverloadGovernor(const OverloadParams& params = OverloadParams()) : params_(params) {}

  /// The stride for the next packet: `queued_events` are waiting, the next packet's included.
  /// `initialising`: the tracker initialises, so the packet is taken or skipped whole
  /// (skipWholePacket) rather than tracked with the stride (and is not counted as strided), and
  /// the initialisation's cost per event is the one that counts.
  int strideFor(size_t queued_events, bool initialising = false);
  /// After a packet: `tracked` events went through the tracker in `seconds` (wall time), the
  /// tracker `initialising` when the packet began (the packet in which tracking starts, with
  /// its detection and catch-up, counts as initialisation). The two costs are kept apart: an
  /// initialisation costs several times a tracked event, and a tracking stride made from its
  /// cost skipped far more than needed right after the start (lost tracks in
  /// tracker_overload.test, BENCHMARKS.md).
  void tracked(size_t tracked, double seconds, bool initialising = false);
  /// Count the events a stride left out.
  void skipped(size_t events) { stats_.events_skipped += events; }
  /// While the tracker initialises, a stride thins out the very edges its detection needs
  /// (every 3rd-41st event of screen_sim.test's recordings gave false initialisations; whole
  /// packets none), so a packet with `stride` > 1 is taken whole or skipped whole instead:
  /// every stride-th packet is taken, the same share of the events (the stride from
  /// strideFor(queued, true)). True: skip this one (counted with its `events`).
  bool skipWholePacket(int stride, size_t events);
  /// Count a packet dropped unprocessed (queue over max_queued_events).
  void dropped(size_t events)
  {
    ++stats_.packets_dropped;
    stats_.events_dropped += events;
  }
  bool overQueueLimit(size_t queued_events) const { return queued_events > params_.max_queued_events; }
  /// Wall seconds per tracked event while tracking (over about the latest 5,000 tracked events;
  /// 0 before the first measurement).
  double secondsPerEvent() const { return tracking_.perEvent(); }
  /// The same while initialising.
  double secondsPerEventInitialising() const { return initialising_.perEvent(); }
  const OverloadStats& stats() const { return stats_; }
  const OverloadParams& params() const { return params_; }

private:
  OverloadParams params_;
  OverloadStats stats_;
  /// Time and events tracked, each earlier packet's share decaying with the events since.
  struct Cost
  {
    double seconds = 0, events = 0;
    double perEvent() const { return events > 0 ? seconds / events : 0.0; }
  };
  Cost tracking_, initialising_;
  uint64_t packet_phase_ = 0;  ///< which packets skipWholePacket takes
};
}  // namespace dvs_line_tracker
