// A serialized dvs_msgs/EventArray (as in a bag or on the wire) converted to events.
#include <dvs_driver/event_bag_io.h>

#include <ros/serialization.h>

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  // What the bag reader does: a count that does not fit the bytes is refused before allocating.
  if (!dvs_driver::checkSerializedEventArray(data, size).empty())
    return 0;
  dvs_msgs::EventArray msg;
  try
  {
    ros::serialization::IStream stream(const_cast<uint8_t*>(data), static_cast<uint32_t>(size));
    ros::serialization::deserialize(stream, msg);
  }
  catch (const std::exception&)
  {
    return 0;  // not a message: rosbag / roscpp report it
  }
  dvs_driver::EventVector events;
  try
  {
    dvs_driver::appendFromMessage(msg, events);
  }
  catch (const std::exception&)
  {
  }
  return 0;
}
