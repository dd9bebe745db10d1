#pragma once
// event_camera_msgs/EventPacket messages (ros-event-camera drivers) in ROS 1 bags, read through
// rosbag's type-agnostic message access (raw serialized bytes), so no event_camera_msgs package
// is needed. Library dvs_driver_ros. Payload decoding: formats/event_packet_decoder.h
// (encodings evt3, mono, libcaer; decoder state carried across messages).
#include <dvs_driver/formats/event_format.h>

#include <memory>
#include <string>
#include <vector>

namespace dvs_driver
{
constexpr const char* kEventPacketType = "event_camera_msgs/EventPacket";
/// MD5 of the ROS 1 definition (msg_ros1/EventPacket.msg).
constexpr const char* kEventPacketMd5 = "8a6101b351a64529ac77bd8b71074e52";
/// The ROS 1 definition as rosbag stores it (with std_msgs/Header expanded), for writers.
extern const char* const kEventPacketDefinition;

/// One EventPacket message parsed from its ROS 1 serialization (events point into the buffer).
struct EventPacketView
{
  uint32_t header_seq = 0;
  int64_t stamp_ns = 0;
  std::string frame_id;
  uint32_t height = 0, width = 0;
  uint64_t seq = 0, time_base = 0;
  std::string encoding;
  bool is_bigendian = false;
  const uint8_t* events = nullptr;
  size_t events_size = 0;
};

/// Parse the ROS 1 serialization of event_camera_msgs/EventPacket: header (uint32 seq, time,
/// string frame_id), uint32 height, uint32 width, uint64 seq, uint64 time_base, string encoding,
/// uint8 is_bigendian, uint32 count + events bytes. Returns false and sets `error` (naming the
/// field) when the bytes are too short or have bytes left over.
bool parseEventPacket(const uint8_t* data, size_t size, EventPacketView& out, std::string& error);

/// Serialize (for tests and writers): the inverse of parseEventPacket.
std::vector<uint8_t> serializeEventPacket(const EventPacketView& msg);

/// Topics of a bag that carry event_camera_msgs/EventPacket messages (sorted).
std::vector<std::string> eventPacketTopics(const std::string& bag_path);

/// Streaming reader of the EventPacket messages on `topic` of a ROS 1 bag ("" = the only, or
/// first, EventPacket topic; a warning names the others). One message is held at a time.
/// Sensor size and encoding from the first message; formatName() e.g.
/// "ROS 1 bag, event_camera_msgs/EventPacket (evt3) on /event_camera/events". EVT 3.0 triggers
/// through takeTriggers(). A message that cannot be parsed is skipped, counted in
/// stats().damaged_packets and warned. Throws EventFormatError naming the problem: not a bag,
/// no EventPacket topic, a topic with another type or MD5, an unsupported encoding, big-endian
/// payloads.
std::unique_ptr<EventFileReader> openEventPacketBag(const std::string& bag_path, const std::string& topic = "");
}  // namespace dvs_driver
