// rostest: a C++ subscriber receives the publisher's EventArrays of 100,000 events through a
// real master and checks that nothing is lost or reordered.
#include <dvs_msgs/EventArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <vector>

namespace
{
std::vector<dvs_msgs::EventArray::ConstPtr> g_received;
void onEvents(const dvs_msgs::EventArray::ConstPtr& msg) { g_received.push_back(msg); }
}  // namespace

TEST(EventArrayTransport, HundredThousandEventsArriveIntactAndInOrder)
{
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  int packets = 3;
  int events = 100000;
  pnh.param("packets", packets, packets);
  pnh.param("events", events, events);
  ros::Subscriber sub = nh.subscribe("events", packets, onEvents);

  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && static_cast<int>(g_received.size()) < packets && ros::WallTime::now() < deadline)
    ros::spinOnce(), ros::WallDuration(0.005).sleep();

  ASSERT_EQ(static_cast<size_t>(packets), g_received.size());
  for (int p = 0; p < packets; ++p)
  {
    const dvs_msgs::EventArray& msg = *g_received[p];
    EXPECT_EQ(ros::Time(1000 + p, 0), msg.header.stamp) << "packets reordered or lost";
    EXPECT_EQ(128u, msg.width);
    EXPECT_EQ(128u, msg.height);
    ASSERT_EQ(static_cast<size_t>(events), msg.events.size());
    for (int i = 0; i < events; ++i)
    {
      const dvs_msgs::Event& e = msg.events[i];
      const long n = static_cast<long>(p) * events + i;
      ASSERT_EQ(n % 128, e.x) << "packet " << p << " event " << i;
      ASSERT_EQ((n / 128) % 128, e.y) << "packet " << p << " event " << i;
      ASSERT_EQ(ros::Time(1000 + p, static_cast<uint32_t>(i) * 1000u + 1u), e.ts) << "packet " << p << " event " << i;
      ASSERT_EQ((n % 2) == 1, static_cast<bool>(e.polarity)) << "packet " << p << " event " << i;
    }
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_event_array_subscriber");
  return RUN_ALL_TESTS();
}
