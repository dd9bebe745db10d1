#pragma once
// Time stamping, packet policy and packet building of the driver (ROS-free, header-only).
#include <dvs_driver/event.h>

#include <chrono>
#include <cstddef>
#include <cstdint>

namespace dvs_driver
{
/// Maps source times (ns since the source's time origin) to absolute stamps (ns):
/// stamp = base + t. The base is the host time of the last timestamp reset. Stamps never go
/// backwards: an earlier stamp is clamped to the last one and counted.
class StampMapper
{
public:
  void setBase(int64_t base_ns) { base_ns_ = base_ns; }
  int64_t base() const { return base_ns_; }
  int64_t map(int64_t t_ns)
  {
    int64_t s = base_ns_ + t_ns;
    if (s < last_ns_)
    {
      ++clamped_;
      s = last_ns_;
    }
    last_ns_ = s;
    return s;
  }
  uint64_t clamped() const { return clamped_; }
  int64_t last() const { return last_ns_; }

private:
  int64_t base_ns_ = 0;
  int64_t last_ns_ = INT64_MIN;
  uint64_t clamped_ = 0;
};

/// When a packet is complete: its events span at least `period_ns` (time of the newest minus
/// time of the oldest event... measured from the packet's first event) or it holds `max_events`.
struct PacketPolicy
{
  int64_t period_ns = 1000000;
  size_t max_events = 100000;
  bool full(int64_t first_ns, int64_t last_ns, size_t count) const
  {
    return count >= max_events || last_ns - first_ns >= period_ns;
  }
};

/// Cuts a stream of events into packets: maps each event's time to its stamp (StampMapper),
/// opens a packet at the first event, closes it when the PacketPolicy says it is full, or when it
/// has waited one period of wall time (flushIfWaited), or on demand (flush). The packet itself
/// belongs to a Sink (the ROS side's message), so nothing here allocates:
///   void begin();                             // a new packet starts
///   void append(const Event& e, int64_t stamp_ns);
///   void finish();                            // the packet is complete: publish it
///   void discard();                           // drop the open packet (nobody listens)
/// Not thread-safe: the caller serialises calls.
class PacketBuilder
{
public:
  using Clock = std::chrono::steady_clock;
  PacketPolicy policy;
  StampMapper stamps;

  template <class Sink>
  void add(const Event* begin, const Event* end, Sink& sink)
  {
    for (const Event* e = begin; e != end; ++e)
    {
      const int64_t s = stamps.map(e->t_ns);
      if (count_ == 0)
      {
        sink.begin();
        first_ns_ = s;
        started_ = Clock::now();
      }
      sink.append(*e, s);
      ++count_;
      if (policy.full(first_ns_, s, count_))
      {
        sink.finish();
        count_ = 0;
      }
    }
  }
  /// Nobody listens: times keep moving (stamps mapped, clamps counted), nothing is built, and an
  /// open packet is dropped.
  template <class Sink>
  void skip(const Event* begin, const Event* end, Sink& sink)
  {
    for (const Event* e = begin; e != end; ++e)
      stamps.map(e->t_ns);
    if (count_ > 0)
      sink.discard();
    count_ = 0;
  }
  /// Close the open packet, if any.
  template <class Sink>
  void flush(Sink& sink)
  {
    if (count_ > 0)
      sink.finish();
    count_ = 0;
  }
  /// Close the open packet if it got its first event at least one period of wall time ago.
  template <class Sink>
  void flushIfWaited(Sink& sink, Clock::time_point now = Clock::now())
  {
    if (count_ > 0 && now - started_ >= std::chrono::nanoseconds(policy.period_ns))
      flush(sink);
  }
  size_t openCount() const { return count_; }

private:
  size_t count_ = 0;
  int64_t first_ns_ = 0;
  Clock::time_point started_;
};
}  // namespace dvs_driver
