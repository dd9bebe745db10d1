#pragma once
// dvs_msgs/EventArray <-> dvs_driver events, and event bags (library dvs_driver_ros).
//
// Time: an Event's t_ns (int64 nanoseconds) maps to ros::Time {sec = t_ns / 1e9,
// nsec = t_ns % 1e9} exactly, both ways. ros::Time cannot hold negative times or times past
// 2106: converting such an event throws EventBagError naming the value.
#include <dvs_driver/event.h>
#include <dvs_driver/event_source.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/formats/event_format.h>
#include <dvs_msgs/EventArray.h>
#include <ros/time.h>

#include <memory>
#include <string>


namespace rosbag
{
class Bag;
}

namespace dvs_driver
{
/// Thrown for unreadable bags, a missing topic (the message lists the topics present), a topic
/// of the wrong type, or times a ros::Time cannot represent.
class EventBagError : public EventFileError
{
public:
  using EventFileError::EventFileError;
};

/// The default event topic of the suite.
constexpr const char* kDefaultEventTopic = "/dvs/events";
/// The default packet period of written bags and of the driver: 1 ms.
constexpr int64_t kDefaultPacketPeriodNs = 1000000;

/// Exact ns -> ros::Time. Throws EventBagError for t_ns < 0 or t_ns >= 2^32 s.
ros::Time nsToRosTime(int64_t t_ns);
/// Exact ros::Time -> ns.
inline int64_t rosTimeToNs(const ros::Time& t)
{
  return static_cast<int64_t>(t.sec) * 1000000000LL + static_cast<int64_t>(t.nsec);
}

/// Append events [begin, end) to msg.events (reserves, never shrinks). Header and size untouched.
void appendToMessage(const Event* begin, const Event* end, dvs_msgs::EventArray& msg);

/// A complete message: events, width, height, header.stamp = time of the last event (zero time
/// for an empty range), header.frame_id = frame_id.
dvs_msgs::EventArrayPtr toMessage(const Event* begin, const Event* end, uint32_t width, uint32_t height,
                                  const std::string& frame_id = "dvs");
dvs_msgs::EventArrayPtr toMessage(const EventStream& stream, const std::string& frame_id = "dvs");

/// Append the events of msg to out (exact ns times).
void appendFromMessage(const dvs_msgs::EventArray& msg, EventVector& out);

/// Check a serialized dvs_msgs/EventArray before deserializing it: its frame_id and event count
/// must fit in its `size` bytes (a corrupt count would make the deserializer allocate up to
/// 64 GB). Returns "" when plausible, else what is wrong.
std::string checkSerializedEventArray(const uint8_t* data, size_t size);
/// The events of msg plus its sensor size.
EventStream fromMessage(const dvs_msgs::EventArray& msg);

/// Read every dvs_msgs/EventArray on `topic` of the bag, in bag order, into one stream. The
/// sensor size is that of the first message with a non-zero size. Throws EventBagError on a
/// missing/unreadable file, a missing topic (listing the topics present with their types), or a
/// topic of another type.
EventStream readEventsBag(const std::string& path, const std::string& topic = kDefaultEventTopic);

/// The events of one topic of a bag, a message at a time (bounded memory; same checks as
/// readEventsBag, which reads through it). The sensor size is that of the first message stating
/// one. Events are delivered in bag order.
class BagEventSource : public EventSource
{
public:
  BagEventSource(const std::string& path, const std::string& topic = kDefaultEventTopic);
  ~BagEventSource() override;
  const EventSourceInfo& info() const override { return info_; }
  size_t read(EventVector& out, size_t max_events) override;
  void rewind() override;

private:
  struct Reader;  // the bag, its view and where the reading stands (rosbag headers stay out)
  std::unique_ptr<Reader> reader_;
  EventSourceInfo info_;
};

/// Any recorded event file for streaming, its format detected from its bytes: a ROS 1 bag of
/// dvs_msgs/EventArray (topic `topic`) or of event_camera_msgs/EventPacket (`topic` when it
/// carries them; with the default topic absent, the bag's first EventPacket topic), Prophesee
/// RAW, AEDAT 3.1/4.0, HDF5 (FormatReaderSource), or what openEventFileSource opens (AEDAT 2.0,
/// events.txt). info().format names what was detected.
std::unique_ptr<EventSource> openEventSource(const std::string& path, const std::string& topic = kDefaultEventTopic);

/// The EventPacket reader (event_packet_bag.h) of a bag that openEventSource reads as
/// event_camera_msgs/EventPacket messages (same rule), else nullptr (not such a bag).
std::unique_ptr<EventFileReader> openEventPacketBagFor(const std::string& path,
                                                       const std::string& topic = kDefaultEventTopic);

/// Write events (sorted by time) to an open bag on `topic`, split into fixed-period packets:
/// packet k holds the events with floor(t_ns / packet_period_ns) == k (periods aligned to
/// multiples of the period in absolute time; empty periods produce no message). Each message's
/// header.stamp AND its bag record time = the time of the packet's LAST event (what a live
/// driver knows when it sends the packet). Returns the number of messages written. Throws
/// EventBagError for packet_period_ns <= 0, times a ros::Time cannot hold, or events that go
/// backwards in time. `progress` (optional) hears the events written so far, every ~65,536.
size_t writeEventsBag(rosbag::Bag& bag, const std::string& topic, const EventVector& events, uint32_t width,
                      uint32_t height, int64_t packet_period_ns = kDefaultPacketPeriodNs,
                      const std::string& frame_id = "dvs", const WriteProgress& progress = {});

class CheckedBagWriter;
/// The same into a checked bag (checked_bag.h): rosbag errors become BagWriteError naming it.
size_t writeEventsBag(CheckedBagWriter& bag, const std::string& topic, const EventVector& events, uint32_t width,
                      uint32_t height, int64_t packet_period_ns = kDefaultPacketPeriodNs,
                      const std::string& frame_id = "dvs", const WriteProgress& progress = {});

/// Convenience: create (overwrite) `path` and write `stream` as above, checked (CheckedBagWriter):
/// a missing folder, a full disk, ... throw BagWriteError naming the bag and the reason, and no
/// bag appears under `path` unless complete.
size_t writeEventsBag(const std::string& path, const std::string& topic, const EventStream& stream,
                      int64_t packet_period_ns = kDefaultPacketPeriodNs, const std::string& frame_id = "dvs",
                      const WriteProgress& progress = {});
}  // namespace dvs_driver
