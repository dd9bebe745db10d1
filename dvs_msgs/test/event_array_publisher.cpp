// Test fixture node: publishes `~packets` EventArrays of `~events` events each on `events`,
// with a known pattern that test_event_array_subscriber.cpp checks, once a subscriber is there.
#include <dvs_msgs/EventArray.h>
#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "event_array_publisher");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  int packets = 3;
  int events = 100000;
  pnh.param("packets", packets, packets);
  pnh.param("events", events, events);
  if (packets <= 0 || events <= 0)
  {
    ROS_FATAL("~packets and ~events must be positive (got %d, %d)", packets, events);
    return 1;
  }
  ros::Publisher pub = nh.advertise<dvs_msgs::EventArray>("events", packets);
  // getNumSubscribers() counts connections whose handshake is done: a message published now
  // reaches the subscriber (no settling delay needed).
  while (ros::ok() && pub.getNumSubscribers() == 0)
    ros::WallDuration(0.01).sleep();

  for (int p = 0; p < packets && ros::ok(); ++p)
  {
    dvs_msgs::EventArrayPtr msg(new dvs_msgs::EventArray);
    msg->header.seq = p;
    msg->header.stamp = ros::Time(1000 + p, 0);
    msg->width = 128;
    msg->height = 128;
    msg->events.resize(events);
    for (int i = 0; i < events; ++i)
    {
      dvs_msgs::Event& e = msg->events[i];
      const long n = static_cast<long>(p) * events + i;
      e.x = static_cast<uint16_t>(n % 128);
      e.y = static_cast<uint16_t>((n / 128) % 128);
      e.ts = ros::Time(1000 + p, static_cast<uint32_t>(i) * 1000u + 1u);
      e.polarity = (n % 2) == 1;
    }
    pub.publish(msg);
  }
  ros::spin();  // stay up until the test ends
  return 0;
}
