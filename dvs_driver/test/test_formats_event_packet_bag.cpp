// ROS 1 bags of event_camera_msgs/EventPacket read through rosbag's type-agnostic access: a bag
// written here (topic_tools::ShapeShifter with our datatype/MD5/definition) from the 105 real
// payloads of the ROS 2 bag sample decodes to the README's known answers; damaged messages,
// missing topics, other definitions.
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_packet_bag.h>
#include <dvs_driver/recording.h>

#include "event_packet_sample_bag.h"
#include "formats_test_util.h"

#include <gtest/gtest.h>

#include <cstdlib>

using namespace dvs_driver;
using formats_test::TempFile;

namespace
{
const char* kTopic = "/event_camera/events";
using event_packet_sample::view;
using event_packet_sample::writeRaw;

/// The sample's packets as a ROS 1 bag; `damage` = index of a message written cut short (-1: none).
void writeSampleBag(const std::string& path, int damage = -1)
{
  EXPECT_EQ(event_packet_sample::writeSampleBag(formats_test::sample("eventpacket_evt3_1280x720_ros2bag.db3"), path,
                                                kTopic, damage),
            105u);
}
}  // namespace

TEST(FormatsEventPacketBag, BagFromTheRealPayloadsGivesTheKnownAnswers)
{
  TempFile f(".bag");
  writeSampleBag(f.path());
  EXPECT_EQ(detectEventFormat(f.path()), EventFormat::RosBag1);
  EXPECT_EQ(eventPacketTopics(f.path()), std::vector<std::string>{kTopic});
  auto r = openEventPacketBag(f.path());
  EXPECT_EQ(r->formatName(), "ROS 1 bag, event_camera_msgs/EventPacket (evt3) on /event_camera/events");
  EXPECT_EQ(r->width(), 1280u);
  EXPECT_EQ(r->height(), 720u);
  EventVector ev, batch;
  std::vector<TriggerEvent> triggers;
  while (r->read(batch, 5000))
  {
    EXPECT_LE(batch.size(), 5000u);
    ev.insert(ev.end(), batch.begin(), batch.end());
    batch.clear();
    r->takeTriggers(triggers);
  }
  ASSERT_EQ(ev.size(), 82469u);
  int64_t on = 0, st = 0, sx = 0, sy = 0;
  for (const auto& e : ev)
  {
    on += e.polarity;
    st += e.t_ns;
    sx += e.x;
    sy += e.y;
  }
  EXPECT_EQ(on, 41439);
  EXPECT_EQ(st, 1222326831810000);
  EXPECT_EQ(sx, 42078718);
  EXPECT_EQ(sy, 31656267);
  EXPECT_EQ(ev.front(), (Event{14224870000, 354, 604, true}));
  EXPECT_EQ(ev.back(), (Event{15476187000, 15, 157, false}));
  ASSERT_EQ(triggers.size(), 2u);
  EXPECT_EQ(triggers[0], (TriggerEvent{14547491000, 0, false}));
  EXPECT_EQ(triggers[1], (TriggerEvent{14549491000, 0, true}));
  const ReaderStats s = r->stats();
  EXPECT_EQ(s.events, 82469u);
  EXPECT_EQ(s.damaged_packets, 0u);
  EXPECT_EQ(s.bytes_read, s.file_size);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  // Python rosbag reads the same bag (message class generated from the stored definition).
  if (std::system("/usr/bin/python3 -c 'import rosbag' 2>/dev/null") == 0)
  {
    size_t payload = 0;
    for (const auto& p : ros2_sample::readBagPackets(formats_test::sample("eventpacket_evt3_1280x720_ros2bag.db3")))
      payload += p.events.size();
    const std::string py =
        "import rosbag, sys\n"
        "n = b = 0\n"
        "for topic, m, t in rosbag.Bag('" + f.path() + "').read_messages(topics=['" + kTopic + "']):\n"
        "    ok = m._type == 'event_camera_msgs/EventPacket' and m.encoding == 'evt3' and m.width == 1280 "
        "and m.height == 720 and m.header.frame_id == '0109'\n"
        "    if not ok: sys.exit(2)\n"
        "    n += 1; b += len(m.events)\n"
        "sys.exit(0 if (n, b) == (105, " + std::to_string(payload) + ") else 1)\n";
    TempFile script(".py");
    script.write(reinterpret_cast<const uint8_t*>(py.data()), py.size());
    EXPECT_EQ(std::system(("/usr/bin/python3 " + script.path()).c_str()), 0) << py;
  }
  // Named topic: the same.
  EXPECT_EQ(openEventPacketBag(f.path(), kTopic)->readAll().size(), 82469u);
}

TEST(FormatsEventPacketBag, DamagedMessageIsSkippedCountedAndWarned)
{
  TempFile f(".bag");
  writeSampleBag(f.path(), 50);
  auto r = openEventPacketBag(f.path());
  const EventVector ev = r->readAll();
  EXPECT_GT(ev.size(), 70000u);
  EXPECT_LT(ev.size(), 82469u);
  const ReaderStats s = r->stats();
  EXPECT_EQ(s.damaged_packets, 1u);
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings[0].find("message 50"), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("too short for field 'events'"), std::string::npos) << s.warnings[0];
}

TEST(FormatsEventPacketBag, NamedErrors)
{
  auto errorOf = [](const std::string& path, const std::string& topic = "") -> std::string {
    try
    {
      openEventPacketBag(path, topic);
    }
    catch (const EventFormatError& e)
    {
      return e.what();
    }
    return "(no error)";
  };
  TempFile none(".bag");
  {
    rosbag::Bag bag(none.path(), rosbag::bagmode::Write);
    std_msgs::String s;
    bag.write("/chatter", ros::Time(1, 0), s);
  }
  std::string e = errorOf(none.path());
  EXPECT_NE(e.find("no event_camera_msgs/EventPacket messages"), std::string::npos) << e;
  EXPECT_NE(e.find("/chatter (std_msgs/String)"), std::string::npos) << e;

  TempFile md5(".bag");
  EventPacketView v;
  v.encoding = "evt3";
  {
    rosbag::Bag bag(md5.path(), rosbag::bagmode::Write);
    writeRaw(bag, kTopic, ros::Time(1, 0), serializeEventPacket(v), "0123456789abcdef0123456789abcdef");
  }
  e = errorOf(md5.path());
  EXPECT_NE(e.find("with MD5 0123456789abcdef0123456789abcdef"), std::string::npos) << e;

  TempFile enc(".bag");
  v.encoding = "libcaer_cmp";
  {
    rosbag::Bag bag(enc.path(), rosbag::bagmode::Write);
    writeRaw(bag, kTopic, ros::Time(1, 0), serializeEventPacket(v));
  }
  e = errorOf(enc.path());
  EXPECT_NE(e.find("encoding 'libcaer_cmp' is not supported"), std::string::npos) << e;
  e = errorOf(enc.path(), "/missing");
  EXPECT_NE(e.find("topic /missing has no"), std::string::npos) << e;

  TempFile notbag(".bag");
  notbag.write(std::vector<uint8_t>{'#', 'R', 'O', 'S', 'B', 'A', 'G'});
  e = errorOf(notbag.path());
  EXPECT_NE(e.find("cannot be read as a ROS 1 bag"), std::string::npos) << e;
}

// The driver's file source (openEventSource, so ~file and replay.launch) and readRecording
// (convert, track_offline, calibrate) read the EventPacket bag as the reader does: decoder state
// carried across messages, the same events in any block size, again after a rewind.
TEST(FormatsEventPacketBag, FileSourceAndReadRecordingGiveTheKnownAnswers)
{
  TempFile f(".bag");
  writeSampleBag(f.path());
  for (const std::string topic : {std::string(kDefaultEventTopic), std::string(kTopic)})
  {
    auto source = openEventSource(f.path(), topic);
    EXPECT_EQ(source->info().format, "ROS 1 bag, event_camera_msgs/EventPacket (evt3) on /event_camera/events");
    EXPECT_EQ(source->info().width, 1280u);
    EXPECT_EQ(source->info().height, 720u);
    for (size_t block : {size_t(1000), size_t(777), size_t(100000)})
    {
      EventVector ev;
      while (source->read(ev, block) > 0)
      {
      }
      ASSERT_EQ(ev.size(), 82469u) << topic << " block " << block;
      EXPECT_EQ(ev.front(), (Event{14224870000, 354, 604, true}));
      EXPECT_EQ(ev.back(), (Event{15476187000, 15, 157, false}));
      int64_t st = 0;
      for (const auto& e : ev)
        st += e.t_ns;
      EXPECT_EQ(st, 1222326831810000);
      source->rewind();
    }
  }
  const Recording r = readRecording(f.path());
  EXPECT_EQ(r.format, "ROS 1 bag, event_camera_msgs/EventPacket (evt3) on /event_camera/events");
  EXPECT_EQ(recordingFormatName(f.path()), r.format);
  ASSERT_EQ(r.contents.stream.events.size(), 82469u);
  EXPECT_EQ(r.contents.stream.width, 1280u);
  EXPECT_EQ(r.contents.stream.events.back(), (Event{15476187000, 15, 157, false}));

  // A topic that is neither: the dvs_msgs bag reader's error listing the topics.
  try
  {
    openEventSource(f.path(), "/nothing");
    ADD_FAILURE() << "no error";
  }
  catch (const EventFileError& e)
  {
    EXPECT_NE(std::string(e.what()).find("no topic /nothing in the bag"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/event_camera/events [event_camera_msgs/EventPacket]"), std::string::npos)
        << e.what();
  }
}

// A dvs_msgs bag that also holds an EventPacket topic: the default topic /dvs/events is read.
TEST(FormatsEventPacketBag, DvsMsgsTopicWinsOverEventPackets)
{
  TempFile f(".bag");
  writeSampleBag(f.path());
  {
    rosbag::Bag bag(f.path(), rosbag::bagmode::Append);
    EventVector ev{{1000, 1, 2, true}, {2000, 3, 4, false}};
    writeEventsBag(bag, kDefaultEventTopic, ev, 128, 128);
  }
  auto source = openEventSource(f.path());
  EXPECT_EQ(source->info().format, "ROS bag, dvs_msgs/EventArray on /dvs/events");
  EventVector ev;
  while (source->read(ev, 100) > 0)
  {
  }
  EXPECT_EQ(ev.size(), 2u);
  EXPECT_EQ(readRecording(f.path()).contents.stream.events.size(), 2u);
}
