// A bag written by another tool (the rosbag Python API, raw messages with the ecosystem's
// type name, MD5 sum and definition text) is read by C++ rosbag::View into our
// dvs_msgs::EventArray with every field intact.
#include <dvs_msgs/EventArray.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace
{
constexpr int kPackets = 3;
constexpr int kEventsPerPacket = 1000;

// Same pattern as event_fields() in write_ecosystem_bag.py.
void expectedEvent(int packet, int i, dvs_msgs::Event& e)
{
  const long n = static_cast<long>(packet) * kEventsPerPacket + i;
  e.x = static_cast<uint16_t>((n * 7) % 128);
  e.y = static_cast<uint16_t>((n * 13) % 128);
  e.ts.sec = static_cast<uint32_t>(1400000000 + packet);
  e.ts.nsec = static_cast<uint32_t>((n * 999983) % 1000000000);
  e.polarity = (n % 3) == 0;
}

std::string writeEcosystemBag()
{
  char dir_template[] = "/tmp/dvs_msgs_bag_XXXXXX";
  const char* dir = mkdtemp(dir_template);
  if (dir == nullptr)
    return "";
  const std::string bag = std::string(dir) + "/ecosystem.bag";
  const std::string cmd = "/usr/bin/python3 " WRITE_BAG_SCRIPT " " + bag;
  if (std::system(cmd.c_str()) != 0)
    return "";
  return bag;
}
}  // namespace

TEST(DvsMsgsBagCompat, EcosystemBagReadsIntoOurType)
{
  const std::string path = writeEcosystemBag();
  ASSERT_FALSE(path.empty()) << "the rosbag Python API could not write the fixture bag";

  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery("/dvs/events"));
  int packet = 0;
  for (const rosbag::MessageInstance& m : view)
  {
    EXPECT_EQ("dvs_msgs/EventArray", m.getDataType());
    EXPECT_EQ("5e8beee5a6c107e504c2e78903c224b8", m.getMD5Sum());
    dvs_msgs::EventArray::ConstPtr msg = m.instantiate<dvs_msgs::EventArray>();
    ASSERT_TRUE(msg != nullptr) << "packet " << packet << " did not instantiate as dvs_msgs::EventArray";
    EXPECT_EQ(static_cast<uint32_t>(17 + packet), msg->header.seq);
    EXPECT_EQ(static_cast<uint32_t>(1400000000 + packet), msg->header.stamp.sec);
    EXPECT_EQ(123456789u, msg->header.stamp.nsec);
    EXPECT_EQ("dvs" + std::to_string(packet), msg->header.frame_id);
    EXPECT_EQ(128u, msg->height);
    EXPECT_EQ(128u, msg->width);
    ASSERT_EQ(static_cast<size_t>(kEventsPerPacket), msg->events.size());
    for (int i = 0; i < kEventsPerPacket; ++i)
    {
      dvs_msgs::Event want;
      expectedEvent(packet, i, want);
      const dvs_msgs::Event& got = msg->events[i];
      ASSERT_EQ(want.x, got.x) << "packet " << packet << " event " << i;
      ASSERT_EQ(want.y, got.y) << "packet " << packet << " event " << i;
      ASSERT_EQ(want.ts.sec, got.ts.sec) << "packet " << packet << " event " << i;
      ASSERT_EQ(want.ts.nsec, got.ts.nsec) << "packet " << packet << " event " << i;
      ASSERT_EQ(want.polarity, got.polarity) << "packet " << packet << " event " << i;
    }
    ++packet;
  }
  EXPECT_EQ(kPackets, packet);
  bag.close();
  std::remove(path.c_str());
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
