// event_camera_msgs/EventPacket payload decoding: the 105 real "evt3" payloads of the ROS 2 bag
// sample (read here with sqlite3 and a small CDR parser, test only) to the README's known
// answers; hand-built "mono" and "libcaer" payloads; state across messages; bad input.
#include <dvs_driver/formats/event_packet_decoder.h>

#include "formats_test_util.h"
#include "ros2_event_packet_sample.h"

#include <cstring>

using namespace dvs_driver;
using namespace dvs_driver::formats;

using ros2_sample::Packet;
using ros2_sample::readBagPackets;

namespace
{
const char* kBag = "eventpacket_evt3_1280x720_ros2bag.db3";

struct Sums
{
  uint64_t n = 0, on = 0;
  int64_t t = 0, x = 0, y = 0;
};

Sums sums(const EventVector& ev)
{
  Sums s;
  for (const auto& e : ev)
  {
    ++s.n;
    s.on += e.polarity;
    s.t += e.t_ns;
    s.x += e.x;
    s.y += e.y;
  }
  return s;
}
}  // namespace

TEST(FormatsEventPacket, RealEvt3PayloadsGiveTheKnownAnswers)
{
  const auto packets = readBagPackets(formats_test::sample(kBag));
  ASSERT_EQ(packets.size(), 105u);
  EXPECT_EQ(packets.front().seq, 59068u);
  EXPECT_EQ(packets.back().seq, 59172u);
  EventPacketDecoder dec;
  EventVector ev;
  std::vector<TriggerEvent> triggers;
  for (const auto& p : packets)
  {
    EXPECT_EQ(p.encoding, "evt3");
    EXPECT_EQ(p.frame_id, "0109");
    EXPECT_EQ(p.width, 1280u);
    EXPECT_EQ(p.height, 720u);
    dec.decode(p.encoding, p.width, p.height, p.time_base, p.events.data(), p.events.size(), ev, &triggers);
  }
  ASSERT_EQ(ev.size(), 82469u);
  const Sums s = sums(ev);
  EXPECT_EQ(s.on, 41439u);
  EXPECT_EQ(s.t, 1222326831810000);
  EXPECT_EQ(s.x, 42078718);
  EXPECT_EQ(s.y, 31656267);
  EXPECT_EQ(ev.front(), (Event{14224870000, 354, 604, true}));
  EXPECT_EQ(ev.back(), (Event{15476187000, 15, 157, false}));
  ASSERT_EQ(triggers.size(), 2u);
  EXPECT_EQ(triggers[0], (TriggerEvent{14547491000, 0, false}));
  EXPECT_EQ(triggers[1], (TriggerEvent{14549491000, 0, true}));
  const ReaderStats& st = dec.stats();
  EXPECT_EQ(st.events, 82469u);
  EXPECT_EQ(st.triggers, 2u);
  EXPECT_EQ(dec.messages(), 105u);
  EXPECT_FALSE(st.truncated);

  // The same stream cut into other pieces (state across messages) gives the same events.
  std::vector<uint8_t> all;
  for (const auto& p : packets)
    all.insert(all.end(), p.events.begin(), p.events.end());
  for (size_t piece_words : {1u, 3u, 1000u, 100000u})
  {
    EventPacketDecoder d2;
    EventVector ev2;
    for (size_t off = 0; off < all.size(); off += piece_words * 2)
      d2.decode("evt3", 1280, 720, 0, all.data() + off, std::min(piece_words * 2, all.size() - off), ev2);
    EXPECT_TRUE(ev2 == ev) << piece_words;
  }
}

TEST(FormatsEventPacket, MonoWords)
{
  auto word = [](uint32_t dt, uint16_t x, uint16_t y, bool p) {
    return uint64_t(dt) | uint64_t(x) << 32 | uint64_t(y & 0x7FFF) << 48 | uint64_t(p) << 63;
  };
  const std::vector<uint64_t> m1 = {word(0, 1, 2, true), word(4000000000u, 639, 479, false), word(5, 640, 0, true)};
  const std::vector<uint64_t> m2 = {word(7, 3, 4, false)};
  EventPacketDecoder dec;
  EventVector ev;
  dec.decode("mono", 640, 480, 1000000000000, reinterpret_cast<const uint8_t*>(m1.data()), m1.size() * 8, ev);
  dec.decode("mono", 640, 480, 2000000000000, reinterpret_cast<const uint8_t*>(m2.data()), m2.size() * 8, ev);
  ASSERT_EQ(ev.size(), 3u);
  EXPECT_EQ(ev[0], (Event{1000000000000, 1, 2, true}));
  EXPECT_EQ(ev[1], (Event{1004000000000, 639, 479, false}));
  EXPECT_EQ(ev[2], (Event{2000000000007, 3, 4, false}));
  EXPECT_EQ(dec.stats().out_of_range, 1u);
}

TEST(FormatsEventPacket, LibcaerPolarityEvents)
{
  auto ev8 = [](uint32_t x, uint32_t y, bool p, bool valid, int32_t ts) {
    std::vector<uint8_t> b(8);
    const uint32_t d = x << 17 | y << 2 | uint32_t(p) << 1 | uint32_t(valid);
    std::memcpy(b.data(), &d, 4);
    std::memcpy(b.data() + 4, &ts, 4);
    return b;
  };
  std::vector<uint8_t> m;
  for (auto b : {ev8(345, 259, true, true, 2147483000), ev8(1, 2, false, false, 2147483100),
                 ev8(7, 8, false, true, 100), ev8(346, 0, true, true, 200)})
    m.insert(m.end(), b.begin(), b.end());
  m.push_back(0xAB);  // an incomplete event
  EventPacketDecoder dec;
  EventVector ev;
  const uint64_t base = 1600000000000000000ull;
  dec.decode("libcaer", 346, 260, base, m.data(), m.size(), ev);
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0], (Event{int64_t(base + 2147483000ull * 1000), 345, 259, true}));
  // ts dropped from 2147483100 to 100 inside the message: + 2^31 us
  EXPECT_EQ(ev[1], (Event{int64_t(base + ((1ull << 31) + 100) * 1000), 7, 8, false}));
  const ReaderStats& s = dec.stats();
  EXPECT_EQ(s.invalid_events, 1u);
  EXPECT_EQ(s.out_of_range, 1u);
  EXPECT_EQ(s.time_wraps, 1u);
  EXPECT_TRUE(s.truncated);
  EXPECT_EQ(s.truncated_bytes, 1u);
  EXPECT_EQ(s.truncated_offset, 32u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("not a whole number of 8-byte words"), std::string::npos) << s.warnings[0];
  // The next message starts from its own time_base (rollovers only inside a message).
  const auto next = ev8(9, 9, true, true, 50);
  dec.decode("libcaer", 346, 260, base + 5000, next.data(), next.size(), ev);
  ASSERT_EQ(ev.size(), 3u);
  EXPECT_EQ(ev[2].t_ns, int64_t(base + 5000 + 50000));
}

TEST(FormatsEventPacket, UnsupportedEncodingAndChangesAreNamed)
{
  EventPacketDecoder dec;
  EventVector ev;
  const uint8_t b[8] = {};
  try
  {
    dec.decode("libcaer_cmp", 640, 480, 0, b, 8, ev);
    ADD_FAILURE() << "libcaer_cmp accepted";
  }
  catch (const EventFormatError& e)
  {
    EXPECT_NE(std::string(e.what()).find("'libcaer_cmp' is not supported"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(EventPacketDecoder::supports("trigger"));
  EXPECT_TRUE(EventPacketDecoder::supports("evt3"));
  dec.decode("mono", 640, 480, 0, b, 8, ev);
  try
  {
    dec.decode("evt3", 640, 480, 0, b, 8, ev);
    ADD_FAILURE() << "encoding change accepted";
  }
  catch (const EventFormatError& e)
  {
    EXPECT_NE(std::string(e.what()).find("started with 'mono'"), std::string::npos) << e.what();
  }
  dec.reset();
  EXPECT_NO_THROW(dec.decode("evt3", 640, 480, 0, b, 8, ev));
}
