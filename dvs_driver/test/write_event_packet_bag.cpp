// Test tool: write_event_packet_bag DB3 OUT.bag [TOPIC]
// The EventPacket messages of a ROS 2 bag (sqlite3, CDR; the sample in ../shared/data/formats)
// as a ROS 1 bag of event_camera_msgs/EventPacket on TOPIC (default /event_camera/events), for
// the rostests that replay it (dvs_launch's replay_formats.test). Exit 1 with a message on error.
#include "event_packet_sample_bag.h"

#include <iostream>

int main(int argc, char** argv)
{
  if (argc < 3 || argc > 4)
  {
    std::cerr << "usage: write_event_packet_bag DB3 OUT.bag [TOPIC]\n";
    return 2;
  }
  try
  {
    const size_t n = event_packet_sample::writeSampleBag(argv[1], argv[2], argc > 3 ? argv[3] : "/event_camera/events");
    std::cout << argv[2] << ": " << n << " EventPacket messages\n";
  }
  catch (const std::exception& e)
  {
    std::cerr << "write_event_packet_bag: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
