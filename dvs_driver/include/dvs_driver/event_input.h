#pragma once
// One input interface for live cameras and recorded files (ROS-free). An input delivers chunks
// of events on its own thread; the driver node turns them into EventArray packets.
#include <dvs_driver/event.h>

#include <string>

namespace dvs_driver
{
class EventInputListener
{
public:
  virtual ~EventInputListener() = default;
  /// Events in time order. t_ns is the source's time: device time since its last timestamp reset
  /// for a camera, the file's time for a recording. The range is valid during the call only.
  virtual void onEvents(const Event* begin, const Event* end) = 0;
  /// The source's time restarted at 0 (camera timestamp reset marker).
  virtual void onTimestampReset() {}
  /// A timestamp reset request is about to be sent to the camera (its marker follows).
  virtual void onTimestampResetRequest() {}
  /// Connected / disconnected (camera) with a human-readable reason.
  virtual void onStatus(bool /*connected*/, const std::string& /*message*/) {}
  virtual void onWarning(const std::string& /*message*/) {}
  /// A recording has been delivered completely.
  virtual void onEndOfInput() {}
  /// A recording turned out malformed part way through (the message names the file and where);
  /// the events before the fault were delivered, nothing follows.
  virtual void onInputError(const std::string& message) { onWarning(message); }
};

class EventInput
{
public:
  virtual ~EventInput() = default;
  /// Start delivering on the input's own thread; returns immediately. May throw on bad setup.
  virtual void start(EventInputListener& listener) = 0;
  /// Stop and join the thread. Safe to call twice.
  virtual void stop() = 0;
  virtual std::string description() const = 0;
};
}  // namespace dvs_driver
