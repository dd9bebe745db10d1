#pragma once
// Time stamping and packet policy of the driver (ROS-free parts, header-only).
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
}  // namespace dvs_driver
