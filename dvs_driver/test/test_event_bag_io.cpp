#include <dvs_driver/event_bag_io.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <functional>
#include <std_msgs/String.h>

#include <cstdio>
#include <string>
#include <unistd.h>

using dvs_driver::Event;
using dvs_driver::EventBagError;

namespace
{
std::string tempPath(const std::string& name)
{
  return "/tmp/dvs_driver_test_" + std::to_string(::getpid()) + "_" + name;
}

dvs_driver::EventVector makeEvents(size_t n, int64_t t0_ns)
{
  dvs_driver::EventVector ev;
  for (size_t i = 0; i < n; ++i)
  {
    Event e;
    e.t_ns = t0_ns + static_cast<int64_t>(i) * 333337 + (i % 7);  // odd ns values
    e.x = static_cast<uint16_t>((i * 13) % 128);
    e.y = static_cast<uint16_t>((i * 29) % 128);
    e.polarity = (i % 3) != 0;
    ev.push_back(e);
  }
  return ev;
}

std::string errorOf(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const EventBagError& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(EventBagIo, RosTimeConversionIsExact)
{
  const int64_t t = 1468940843123456789LL;
  const ros::Time rt = dvs_driver::nsToRosTime(t);
  EXPECT_EQ(1468940843u, rt.sec);
  EXPECT_EQ(123456789u, rt.nsec);
  EXPECT_EQ(t, dvs_driver::rosTimeToNs(rt));
  EXPECT_EQ(0, dvs_driver::rosTimeToNs(dvs_driver::nsToRosTime(0)));
  EXPECT_THROW(dvs_driver::nsToRosTime(-1), EventBagError);
  EXPECT_THROW(dvs_driver::nsToRosTime((int64_t(UINT32_MAX) + 1) * 1000000000LL), EventBagError);
}

TEST(EventBagIo, MessageRoundTripKeepsEveryField)
{
  dvs_driver::EventStream s;
  s.events = makeEvents(1000, 5000000001LL);
  s.width = 128;
  s.height = 128;
  const dvs_msgs::EventArrayPtr msg = dvs_driver::toMessage(s, "dvs");
  ASSERT_EQ(1000u, msg->events.size());
  EXPECT_EQ(128u, msg->width);
  EXPECT_EQ(s.events.back().t_ns, dvs_driver::rosTimeToNs(msg->header.stamp));
  EXPECT_EQ(5u, msg->events[0].ts.sec);
  EXPECT_EQ(1u, msg->events[0].ts.nsec);
  const dvs_driver::EventStream back = dvs_driver::fromMessage(*msg);
  ASSERT_EQ(s.events.size(), back.events.size());
  for (size_t i = 0; i < s.events.size(); ++i)
    ASSERT_EQ(s.events[i], back.events[i]) << i;
  EXPECT_EQ(128u, back.height);
}

TEST(EventBagIo, BagRoundTripExactNanosecondsAndOneMsPackets)
{
  dvs_driver::EventStream s;
  s.events = makeEvents(20000, 1000000000LL * 7 + 123);
  s.width = 128;
  s.height = 128;
  const std::string path = tempPath("roundtrip.bag");
  const size_t packets = dvs_driver::writeEventsBag(path, "/dvs/events", s);
  // Count the distinct 1 ms periods the events fall into: one packet each.
  size_t expected_packets = 0;
  int64_t last_period = -1;
  for (const Event& e : s.events)
    if (e.t_ns / 1000000 != last_period)
    {
      ++expected_packets;
      last_period = e.t_ns / 1000000;
    }
  EXPECT_EQ(expected_packets, packets);

  const dvs_driver::EventStream back = dvs_driver::readEventsBag(path);
  EXPECT_EQ(128u, back.width);
  EXPECT_EQ(128u, back.height);
  ASSERT_EQ(s.events.size(), back.events.size());
  for (size_t i = 0; i < s.events.size(); ++i)
    ASSERT_EQ(s.events[i], back.events[i]) << i;

  // Each packet lies within one period, and its stamp is its last event's time.
  rosbag::Bag bag(path);
  rosbag::View view(bag);
  size_t n = 0;
  for (const rosbag::MessageInstance& m : view)
  {
    auto msg = m.instantiate<dvs_msgs::EventArray>();
    ASSERT_TRUE(msg);
    ASSERT_FALSE(msg->events.empty());
    const int64_t first = dvs_driver::rosTimeToNs(msg->events.front().ts);
    const int64_t last = dvs_driver::rosTimeToNs(msg->events.back().ts);
    EXPECT_EQ(first / 1000000, last / 1000000);
    EXPECT_EQ(last, dvs_driver::rosTimeToNs(msg->header.stamp));
    EXPECT_EQ(last, dvs_driver::rosTimeToNs(m.getTime()));
    ++n;
  }
  EXPECT_EQ(packets, n);
  std::remove(path.c_str());
}

TEST(EventBagIo, BagSourceStreamsTheSameEventsInAnyBlockSize)
{
  dvs_driver::EventStream s;
  s.events = makeEvents(20000, 1000000000LL * 3);
  s.width = 240;
  s.height = 180;
  const std::string path = tempPath("stream.bag");
  dvs_driver::writeEventsBag(path, "/dvs/events", s);
  auto source = dvs_driver::openEventSource(path);
  EXPECT_EQ(240u, source->info().width);
  EXPECT_EQ(180u, source->info().height);
  for (size_t block : {1u, 333u, 100000u})
  {
    SCOPED_TRACE(block);
    source->rewind();
    dvs_driver::EventVector got;
    size_t n;
    while ((n = source->read(got, block)) > 0)
      ASSERT_LE(n, block);  // never more than asked: memory bounded by the block
    ASSERT_EQ(s.events.size(), got.size());
    for (size_t i = 0; i < got.size(); ++i)
      ASSERT_EQ(s.events[i], got[i]) << i;
  }
  std::remove(path.c_str());
}

TEST(EventBagIo, CustomPeriodAndTopic)
{
  dvs_driver::EventVector ev = makeEvents(300, 0);  // 0 .. ~100 ms
  const std::string path = tempPath("period.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    EXPECT_EQ(4u, dvs_driver::writeEventsBag(bag, "/cam0/events", ev, 240, 180, 30000000));
  }
  const dvs_driver::EventStream back = dvs_driver::readEventsBag(path, "/cam0/events");
  EXPECT_EQ(240u, back.width);
  EXPECT_EQ(180u, back.height);
  EXPECT_EQ(ev.size(), back.events.size());
  std::remove(path.c_str());
}

TEST(EventBagIo, ClearErrors)
{
  EXPECT_NE(std::string::npos, errorOf([] { dvs_driver::readEventsBag("/nonexistent/x.bag"); }).find("does not exist"));

  const std::string path = tempPath("other.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    std_msgs::String s;
    s.data = "hello";
    bag.write("/chatter", ros::Time(1), s);
    bag.write("/dvs/events", ros::Time(1), s);
  }
  const std::string missing = errorOf([&] { dvs_driver::readEventsBag(path, "/cam/events"); });
  EXPECT_NE(std::string::npos, missing.find("no topic /cam/events")) << missing;
  EXPECT_NE(std::string::npos, missing.find("/chatter [std_msgs/String]")) << missing;
  const std::string wrong = errorOf([&] { dvs_driver::readEventsBag(path); });
  EXPECT_NE(std::string::npos, wrong.find("type std_msgs/String")) << wrong;
  std::remove(path.c_str());

  const std::string garbage = tempPath("garbage.bag");
  {
    FILE* f = std::fopen(garbage.c_str(), "w");
    std::fputs("this is not a bag\n", f);
    std::fclose(f);
  }
  EXPECT_NE(std::string::npos, errorOf([&] { dvs_driver::readEventsBag(garbage); }).find("cannot open bag"));
  std::remove(garbage.c_str());

  rosbag::Bag bag(tempPath("neg.bag"), rosbag::bagmode::Write);
  dvs_driver::EventVector neg = makeEvents(3, -1000);
  EXPECT_NE(std::string::npos, errorOf([&] { dvs_driver::writeEventsBag(bag, "/dvs/events", neg, 128, 128); })
                                   .find("cannot be stored as a ros::Time"));
  dvs_driver::EventVector back = makeEvents(3, 1000);
  std::swap(back[0], back[2]);
  EXPECT_NE(std::string::npos,
            errorOf([&] { dvs_driver::writeEventsBag(bag, "/dvs/events", back, 128, 128); }).find("back in time"));
  EXPECT_THROW(dvs_driver::writeEventsBag(bag, "/dvs/events", back, 128, 128, 0), EventBagError);
  bag.close();
  std::remove(tempPath("neg.bag").c_str());
}

TEST(EventBagIo, ImpossibleEventCountsAreRefusedBeforeAllocating)
{
  // Found by fuzzing: a corrupt count made the deserializer allocate ~13 GB.
  dvs_driver::EventVector events(3);
  for (size_t i = 0; i < events.size(); ++i)
    events[i] = dvs_driver::Event{static_cast<int64_t>(1000 + i), static_cast<uint16_t>(i), 7, i % 2 == 0};
  const dvs_msgs::EventArrayPtr msg = dvs_driver::toMessage(events.data(), events.data() + events.size(), 128, 128, "dvs");
  std::vector<uint8_t> raw(ros::serialization::serializationLength(*msg));
  ros::serialization::OStream out(raw.data(), static_cast<uint32_t>(raw.size()));
  ros::serialization::serialize(out, *msg);
  EXPECT_EQ(dvs_driver::checkSerializedEventArray(raw.data(), raw.size()), "");
  // The count sits after seq, stamp, frame_id ("dvs"), height and width.
  const size_t count_at = 16 + 3 + 8;
  ASSERT_EQ(raw[count_at], 3);
  raw[count_at + 3] = 0x40;  // ~1e9 events
  EXPECT_NE(dvs_driver::checkSerializedEventArray(raw.data(), raw.size()).find("event count"), std::string::npos);
  EXPECT_NE(dvs_driver::checkSerializedEventArray(raw.data(), 10).find("shorter than"), std::string::npos);
}
