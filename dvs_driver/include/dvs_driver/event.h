#pragma once
// The ROS-free event type every core library of the suite speaks.
#include <cstdint>
#include <vector>

namespace dvs_driver
{
/// One DVS event. Pixel (0,0) is the top-left pixel; polarity true = ON = brightness increase.
struct Event
{
  int64_t t_ns = 0;   ///< time stamp, nanoseconds (the file's or device's time base)
  uint16_t x = 0;     ///< column
  uint16_t y = 0;     ///< row
  bool polarity = false;
};

inline bool operator==(const Event& a, const Event& b)
{
  return a.t_ns == b.t_ns && a.x == b.x && a.y == b.y && a.polarity == b.polarity;
}

using EventVector = std::vector<Event>;

/// Events plus the sensor size they were recorded with (0 when the source does not say).
struct EventStream
{
  EventVector events;
  uint32_t width = 0;
  uint32_t height = 0;
};
}  // namespace dvs_driver
