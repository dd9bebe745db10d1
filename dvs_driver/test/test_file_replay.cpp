// rostest: the driver (node or nodelet) replays a real AEDAT recording on /dvs/events; every
// event arrives, in order, with the file's time differences kept to the nanosecond, in packets
// that respect the packet period.
#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_msgs/EventArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <mutex>

namespace
{
std::mutex g_mutex;
std::vector<dvs_msgs::EventArrayConstPtr> g_packets;
size_t g_events = 0;

void callback(const dvs_msgs::EventArrayConstPtr& msg)
{
  std::lock_guard<std::mutex> lock(g_mutex);
  g_packets.push_back(msg);
  g_events += msg->events.size();
}
}  // namespace

TEST(FileReplay, PublishesEveryEventOfTheRecording)
{
  ros::NodeHandle pnh("~");
  std::string file;
  double period = 0.001;
  ASSERT_TRUE(pnh.getParam("file", file));
  pnh.getParam("packet_period", period);
  const auto rec = dvs_driver::readAedat(file);
  const size_t expected = rec.stream.events.size();
  ASSERT_EQ(19182u, expected);

  ros::NodeHandle nh;
  const int64_t subscribed_ns = dvs_driver::rosTimeToNs(ros::Time::now());
  ros::Subscriber sub = nh.subscribe("/dvs/events", 100000, callback);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::ok() && ros::WallTime::now() < deadline)
  {
    {
      std::lock_guard<std::mutex> lock(g_mutex);
      if (g_events >= expected)
        break;
    }
    ros::WallDuration(0.01).sleep();
  }
  ros::WallDuration(0.2).sleep();  // anything extra would arrive now
  std::lock_guard<std::mutex> lock(g_mutex);
  // roscpp numbers the packets it publishes (header.seq): a gap is a packet published but lost
  // on the way (the publisher's queue for this subscriber overflowed).
  size_t seq_gaps = 0;
  for (size_t i = 1; i < g_packets.size(); ++i)
    seq_gaps += g_packets[i]->header.seq != g_packets[i - 1]->header.seq + 1;
  EXPECT_EQ(0u, seq_gaps) << "packets lost between the driver and this subscriber";
  ASSERT_EQ(expected, g_events) << g_packets.size() << " packets received";

  // ~wait_for_subscriber with ~file_time replay: the first event is stamped with the time the
  // replay started, which is after this test subscribed.
  EXPECT_GE(dvs_driver::rosTimeToNs(g_packets.front()->events.front().ts), subscribed_ns);

  const int64_t period_ns = static_cast<int64_t>(period * 1e9 + 0.5);
  size_t k = 0;
  int64_t stamp0 = 0;
  for (const auto& p : g_packets)
  {
    ASSERT_FALSE(p->events.empty());
    EXPECT_EQ(128u, p->width);
    EXPECT_EQ(128u, p->height);
    EXPECT_EQ("dvs", p->header.frame_id);
    EXPECT_EQ(p->events.back().ts, p->header.stamp);
    const int64_t first = dvs_driver::rosTimeToNs(p->events.front().ts);
    // Every event but the one that completed the packet lies within one period of the first.
    if (p->events.size() >= 2)
      EXPECT_LT(dvs_driver::rosTimeToNs(p->events[p->events.size() - 2].ts) - first, period_ns);
    for (const auto& e : p->events)
    {
      const auto& ref = rec.stream.events[k];
      if (k == 0)
        stamp0 = dvs_driver::rosTimeToNs(e.ts);
      ASSERT_EQ(ref.x, e.x) << k;
      ASSERT_EQ(ref.y, e.y) << k;
      ASSERT_EQ(ref.polarity, e.polarity) << k;
      ASSERT_EQ(ref.t_ns - rec.stream.events[0].t_ns, dvs_driver::rosTimeToNs(e.ts) - stamp0) << k;
      ++k;
    }
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_file_replay");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
