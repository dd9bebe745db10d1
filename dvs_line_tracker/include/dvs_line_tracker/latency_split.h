#pragma once
// The live event-to-pose latency split into its parts (issue 16), ROS-free: for every event
// processed by the node, the time from the event to the publication of its pose, and the parts:
//   accumulation  event -> the last event of its packet (the packet cannot leave before it)
//   transport     the packet's last event -> its arrival in the tracker's callback (on the ROS
//                 clock, the events' time base: live, or a replay with use_sim_time)
//   queue         arrival -> the tracking thread takes the packet (wall time)
//   processing    the tracker's work on the packet (wall time; every event's pose is published
//                 after it, in the ~poses batch, odometry and TF)
//   publishing    the packet's publications (~poses batch, odometry, TF, image, markers)
// Each part is counted once per event of the packet (weights), so that its percentiles are over
// events like the total's. Cumulative since the start (or reset()); fixed memory.
#include <dvs_line_tracker/latency_histogram.h>

#include <cstdint>

namespace dvs_line_tracker
{
struct PacketTiming
{
  int64_t last_event_ns = 0;     ///< time stamp of the packet's last event
  int64_t arrival_clock_ns = 0;  ///< the ROS clock when the packet arrived
  double queue_s = 0;
  double processing_s = 0;
  double publishing_s = 0;
  uint64_t events = 0;
};

class LatencySplit
{
public:
  /// Beyond this, the clock is not the events' (a replay without use_sim_time): the packet's
  /// transport and total are not counted, the packet is counted in clockMismatches().
  static constexpr double kMaxClockOffsetS = 10.0;

  /// One packet's timing (counted for each of its events), then addEvent() for each event.
  void beginPacket(const PacketTiming& p);
  /// One event of the current packet (allocation-free).
  void addEvent(int64_t t_ns)
  {
    const double acc = 1e-9 * double(last_event_ns_ - t_ns);
    accumulation_.add(acc);
    if (clock_ok_)
      total_.add(acc + after_last_event_s_);
  }
  void reset();

  const LatencyHistogram& total() const { return total_; }
  const LatencyHistogram& accumulation() const { return accumulation_; }
  const LatencyHistogram& transport() const { return transport_; }
  const LatencyHistogram& queue() const { return queue_; }
  const LatencyHistogram& processing() const { return processing_; }
  const LatencyHistogram& publishing() const { return publishing_; }
  uint64_t clockMismatches() const { return clock_mismatches_; }

private:
  LatencyHistogram total_, accumulation_, transport_, queue_, processing_, publishing_;
  int64_t last_event_ns_ = 0;
  double after_last_event_s_ = 0;  ///< transport + queue + processing + publishing of the packet
  bool clock_ok_ = false;
  uint64_t clock_mismatches_ = 0;
};
}  // namespace dvs_line_tracker
