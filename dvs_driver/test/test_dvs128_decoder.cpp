#include <dvs_driver/dvs128_decoder.h>
#include <gtest/gtest.h>

#include <random>
#include <vector>

using dvs_driver::Dvs128Decoder;

namespace
{
struct Record
{
  char kind;  // 'e' event, 's' sync, 'r' reset, 'n' non-monotonic
  int64_t t_us;
  int x, y;
  bool pol;
  bool operator==(const Record& o) const
  {
    return kind == o.kind && t_us == o.t_us && x == o.x && y == o.y && pol == o.pol;
  }
};

std::ostream& operator<<(std::ostream& os, const Record& r)
{
  return os << r.kind << " t=" << r.t_us << " (" << r.x << "," << r.y << ") " << r.pol;
}

struct Recorder : dvs_driver::Dvs128ConsumerBase
{
  std::vector<Record> r;
  void event(int64_t t, uint16_t x, uint16_t y, bool p) { r.push_back({'e', t, x, y, p}); }
  void sync(int64_t t) { r.push_back({'s', t, -1, -1, false}); }
  void timestampReset() { r.push_back({'r', 0, -1, -1, false}); }
  void nonMonotonic(int64_t, int64_t t) { r.push_back({'n', t, -1, -1, false}); }
};

// Word bytes of a pixel event as the camera sends them: raw (unflipped) column/row.
std::vector<uint8_t> pixelWord(int raw_x, int raw_y, bool off, uint16_t ts)
{
  const uint16_t addr = static_cast<uint16_t>((raw_y << 8) | (raw_x << 1) | (off ? 1 : 0));
  return {uint8_t(addr & 0xFF), uint8_t(addr >> 8), uint8_t(ts & 0xFF), uint8_t((ts >> 8) & 0x3F)};
}
const std::vector<uint8_t> kWrap = {0, 0, 0, 0x80};
const std::vector<uint8_t> kReset = {0, 0, 0, 0x40};

std::vector<uint8_t> cat(std::initializer_list<std::vector<uint8_t>> parts)
{
  std::vector<uint8_t> out;
  for (const auto& p : parts)
    out.insert(out.end(), p.begin(), p.end());
  return out;
}
}  // namespace

TEST(Dvs128Decoder, PixelFlipsAndPolarityKnownAnswers)
{
  // raw (0,0) ON -> top-left after flips is (127,127); raw (127,127) OFF -> (0,0).
  const auto bytes = cat({pixelWord(0, 0, false, 5), pixelWord(127, 127, true, 6), pixelWord(10, 100, false, 7)});
  Dvs128Decoder d;
  Recorder rec;
  d.decode(bytes.data(), bytes.size(), rec);
  const std::vector<Record> expect = {{'e', 5, 127, 127, true}, {'e', 6, 0, 0, false}, {'e', 7, 117, 27, true}};
  EXPECT_EQ(expect, rec.r);
  EXPECT_EQ(3u, d.stats().events);
  // Byte-level known answer from formats.md: address 0x7683 -> x 62, row 9, OFF.
  const uint8_t w[4] = {0x83, 0x76, 0x10, 0x00};
  Recorder rec2;
  Dvs128Decoder d2;
  d2.decode(w, 4, rec2);
  ASSERT_EQ(1u, rec2.r.size());
  EXPECT_EQ((Record{'e', 16, 62, 9, false}), rec2.r[0]);
}

TEST(Dvs128Decoder, WrapMarkersAdd16384usIn64Bits)
{
  std::vector<uint8_t> bytes = pixelWord(1, 1, false, 100);
  // 300,000 wraps: 4.9e9 us, beyond 32 bits.
  const int wraps = 300000;
  for (int i = 0; i < wraps; ++i)
    bytes.insert(bytes.end(), kWrap.begin(), kWrap.end());
  const auto last = pixelWord(1, 1, false, 3);
  bytes.insert(bytes.end(), last.begin(), last.end());
  Dvs128Decoder d;
  Recorder rec;
  d.decode(bytes.data(), bytes.size(), rec);
  ASSERT_EQ(2u, rec.r.size());
  EXPECT_EQ(100, rec.r[0].t_us);
  EXPECT_EQ(int64_t(wraps) * 16384 + 3, rec.r[1].t_us);
  EXPECT_GT(rec.r[1].t_us, int64_t(1) << 32);
  EXPECT_EQ(uint64_t(wraps), d.stats().wraps);
}

TEST(Dvs128Decoder, ResetMarkerRestartsTimeWithoutWarning)
{
  const auto bytes = cat({kWrap, pixelWord(3, 4, true, 50), kReset, pixelWord(3, 4, true, 2), kWrap,
                          pixelWord(5, 6, false, 1)});
  Dvs128Decoder d;
  Recorder rec;
  d.decode(bytes.data(), bytes.size(), rec);
  const std::vector<Record> expect = {{'e', 16434, 124, 123, false},
                                      {'r', 0, -1, -1, false},
                                      {'e', 2, 124, 123, false},
                                      {'e', 16385, 122, 121, true}};
  EXPECT_EQ(expect, rec.r);
  EXPECT_EQ(1u, d.stats().resets);
  EXPECT_EQ(0u, d.stats().non_monotonic);
}

TEST(Dvs128Decoder, ExternalSyncEventsAreNotPixels)
{
  const std::vector<uint8_t> sync = {0x00, 0x80, 0x20, 0x00};  // addr bit 15, ts 32
  const auto bytes = cat({pixelWord(0, 0, false, 10), sync, pixelWord(0, 0, false, 40)});
  Dvs128Decoder d;
  Recorder rec;
  d.decode(bytes.data(), bytes.size(), rec);
  const std::vector<Record> expect = {
      {'e', 10, 127, 127, true}, {'s', 32, -1, -1, false}, {'e', 40, 127, 127, true}};
  EXPECT_EQ(expect, rec.r);
  EXPECT_EQ(1u, d.stats().sync_events);
  EXPECT_EQ(2u, d.stats().events);
}

TEST(Dvs128Decoder, WordsSplitAcrossTransfersEveryWay)
{
  const auto bytes = cat({pixelWord(1, 2, false, 10), kWrap, pixelWord(3, 4, true, 20), pixelWord(5, 6, false, 30),
                          kReset, pixelWord(7, 8, true, 1)});
  Dvs128Decoder whole;
  Recorder expect;
  whole.decode(bytes.data(), bytes.size(), expect);
  ASSERT_EQ(5u, expect.r.size());
  // Every split into three transfers, including empty ones.
  for (size_t a = 0; a <= bytes.size(); ++a)
    for (size_t b = a; b <= bytes.size(); ++b)
    {
      Dvs128Decoder d;
      Recorder rec;
      d.decode(bytes.data(), a, rec);
      d.decode(bytes.data() + a, b - a, rec);
      d.decode(bytes.data() + b, bytes.size() - b, rec);
      ASSERT_EQ(expect.r, rec.r) << "split at " << a << ", " << b;
      ASSERT_EQ(0u, d.pendingBytes());
    }
  // Byte by byte.
  Dvs128Decoder d;
  Recorder rec;
  for (uint8_t byte : bytes)
    d.decode(&byte, 1, rec);
  EXPECT_EQ(expect.r, rec.r);
  // A trailing partial word waits.
  Dvs128Decoder p;
  Recorder none;
  p.decode(bytes.data(), 3, none);
  EXPECT_TRUE(none.r.empty());
  EXPECT_EQ(3u, p.pendingBytes());
}

TEST(Dvs128Decoder, BackwardsTimeIsWarnedAndClamped)
{
  const auto bytes = cat({pixelWord(0, 0, false, 500), pixelWord(1, 0, false, 200), pixelWord(2, 0, false, 600)});
  Dvs128Decoder d;
  Recorder rec;
  d.decode(bytes.data(), bytes.size(), rec);
  const std::vector<Record> expect = {{'e', 500, 127, 127, true},
                                      {'n', 200, -1, -1, false},
                                      {'e', 500, 126, 127, true},
                                      {'e', 600, 125, 127, true}};
  EXPECT_EQ(expect, rec.r);
  EXPECT_EQ(1u, d.stats().non_monotonic);
}

TEST(Dvs128Decoder, GarbageNeverCrashesAndStaysInRangeAndMonotonic)
{
  std::mt19937 rng(42);
  std::vector<uint8_t> bytes(1 << 20);
  for (auto& b : bytes)
    b = static_cast<uint8_t>(rng());
  Dvs128Decoder d;
  struct Check : dvs_driver::Dvs128ConsumerBase
  {
    int64_t last = 0;
    bool ok = true;
    size_t n = 0;
    void event(int64_t t, uint16_t x, uint16_t y, bool)
    {
      ok = ok && x < 128 && y < 128 && t >= last;
      last = t;
      ++n;
    }
    void timestampReset() { last = 0; }
  } check;
  size_t pos = 0;
  while (pos < bytes.size())  // uneven transfers
  {
    const size_t n = std::min<size_t>(bytes.size() - pos, 1 + rng() % 1000);
    d.decode(bytes.data() + pos, n, check);
    pos += n;
  }
  EXPECT_TRUE(check.ok);
  const auto& s = d.stats();
  EXPECT_EQ(bytes.size() / 4, s.words);
  EXPECT_EQ(s.words, s.events + s.sync_events + s.wraps + s.resets);
  EXPECT_EQ(check.n, s.events);
  EXPECT_GT(s.non_monotonic, 0u);  // random times go backwards, and are reported
}

TEST(Dvs128Decoder, CollectorGivesNanosecondEvents)
{
  const auto bytes = cat({kWrap, pixelWord(0, 127, true, 7)});
  dvs_driver::EventVector ev;
  dvs_driver::Dvs128EventCollector c(ev);
  Dvs128Decoder d;
  d.decode(bytes.data(), bytes.size(), c);
  ASSERT_EQ(1u, ev.size());
  EXPECT_EQ((16384 + 7) * 1000LL, ev[0].t_ns);
  EXPECT_EQ(127, ev[0].x);
  EXPECT_EQ(0, ev[0].y);
  EXPECT_FALSE(ev[0].polarity);
}
