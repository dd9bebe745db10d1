#pragma once
// Test helper: a ROS 1 bag of event_camera_msgs/EventPacket written from the 105 real payloads of
// the ROS 2 bag sample (ros2_event_packet_sample.h), as raw messages through
// topic_tools::ShapeShifter with our datatype, MD5 and definition (no event_camera_msgs package
// needed). Used by test_formats_event_packet_bag and by write_event_packet_bag (the rostests'
// input). Test code only.
#include <dvs_driver/event_packet_bag.h>

#include "ros2_event_packet_sample.h"

#include <rosbag/bag.h>
#include <ros/serialization.h>
#include <std_msgs/String.h>
#include <topic_tools/shape_shifter.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace event_packet_sample
{
/// Write `bytes` (a serialized message) as one message of type EventPacket (MD5 `md5`).
inline void writeRaw(rosbag::Bag& bag, const std::string& topic, const ros::Time& t, const std::vector<uint8_t>& bytes,
                     const std::string& md5 = dvs_driver::kEventPacketMd5)
{
  topic_tools::ShapeShifter ss;
  ss.morph(md5, dvs_driver::kEventPacketType, dvs_driver::kEventPacketDefinition, "0");
  std::vector<uint8_t> copy = bytes;
  ros::serialization::IStream is(copy.data(), uint32_t(copy.size()));
  ss.read(is);
  bag.write(topic, t, ss);
}

inline dvs_driver::EventPacketView view(const ros2_sample::Packet& p)
{
  dvs_driver::EventPacketView v;
  v.header_seq = uint32_t(p.seq);
  v.stamp_ns = int64_t(p.stamp_sec) * 1000000000 + p.stamp_nsec;
  v.frame_id = p.frame_id;
  v.height = p.height;
  v.width = p.width;
  v.seq = p.seq;
  v.time_base = p.time_base;
  v.encoding = p.encoding;
  v.events = p.events.data();
  v.events_size = p.events.size();
  return v;
}

/// The sample's packets (read from `db3`) as a ROS 1 bag at `bag_path` on `topic`, message i at
/// bag time 10 + i s, after a std_msgs/String on /other; `damage` = index of a message written
/// cut short by 3 bytes (-1: none). Returns the number of EventPacket messages written; throws
/// std::runtime_error when a payload does not survive serialize -> parse.
inline size_t writeSampleBag(const std::string& db3, const std::string& bag_path, const std::string& topic,
                             int damage = -1)
{
  const auto packets = ros2_sample::readBagPackets(db3);
  rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
  std_msgs::String other;
  other.data = "not events";
  bag.write("/other", ros::Time(1, 0), other);
  for (size_t i = 0; i < packets.size(); ++i)
  {
    const dvs_driver::EventPacketView v = view(packets[i]);
    std::vector<uint8_t> bytes = dvs_driver::serializeEventPacket(v);
    dvs_driver::EventPacketView back;
    std::string error;
    if (!dvs_driver::parseEventPacket(bytes.data(), bytes.size(), back, error) || back.events_size != v.events_size)
      throw std::runtime_error("EventPacket " + std::to_string(i) + " does not parse back: " + error);
    if (int(i) == damage)
      bytes.resize(bytes.size() - 3);
    writeRaw(bag, topic, ros::Time(10 + i, 0), bytes);
  }
  bag.close();
  return packets.size();
}
}  // namespace event_packet_sample
