// AEDAT 3.1 reader and writer (no real sample exists): hand-built files with known content,
// round trips, damaged and unsupported files.
#include "formats_test_util.h"

#include <dvs_driver/formats/aedat3.h>

#include <cstring>
#include <random>

using namespace dvs_driver;
using namespace formats_test;

namespace
{
const std::string kHeader =
    "#!AER-DAT3.1\r\n#Format: RAW\r\n#Source 1: DAVIS240C\r\n#Start-Time: 2017-01-01 12:00:00 (TZ+0100)\r\n"
    "#!END-HEADER\r\n";

struct Builder
{
  std::vector<uint8_t> b;
  explicit Builder(const std::string& header = kHeader) : b(header.begin(), header.end()) {}
  void i16(int16_t v) { raw(&v, 2); }
  void i32(int32_t v) { raw(&v, 4); }
  void raw(const void* p, size_t n) { b.insert(b.end(), (const uint8_t*)p, (const uint8_t*)p + n); }
  void packet(int16_t type, int32_t size, int32_t overflow, int32_t capacity, int32_t number)
  {
    i16(type);
    i16(1);
    i32(size);
    i32(4);
    i32(overflow);
    i32(capacity);
    i32(number);
    i32(number);
  }
  void polarity(int x, int y, bool on, int32_t ts, bool valid = true)
  {
    i32(int32_t(uint32_t(x) << 17 | uint32_t(y) << 2 | (on ? 2u : 0u) | (valid ? 1u : 0u)));
    i32(ts);
  }
};
}  // namespace

TEST(FormatsAedat3, HandBuiltPacketsValidityOverflowAndSkippedTypes)
{
  Builder f;
  f.packet(7, 10, 0, 1, 1);  // config packet: skipped
  f.raw("0123456789", 10);
  f.packet(1, 8, 0, 4, 3);  // polarity, 3 events in 4 slots
  f.polarity(10, 20, true, 100);
  f.polarity(11, 21, false, 101, false);  // invalid: skipped
  f.polarity(239, 179, false, 102);
  f.polarity(0, 0, false, 0);  // unused slot
  f.packet(200, 4, 0, 2, 2);   // unknown type: skipped, counted
  f.raw("abcdefgh", 8);
  f.packet(1, 8, 1, 2, 2);  // overflow 1: t = 2^31 + ts
  f.polarity(240, 5, true, 7);  // x 240 outside DAVIS240: dropped
  f.polarity(5, 6, true, 8);
  TempFile t(".aedat");
  t.write(f.b);
  EXPECT_EQ(detectEventFormat(t.path()), EventFormat::Aedat3);
  auto r = openEventFileReader(t.path());
  EXPECT_EQ(r->formatName(), "AEDAT 3.1 (DAVIS240C)");
  EXPECT_EQ(r->width(), 240u);
  EXPECT_EQ(r->height(), 180u);
  const int64_t o = int64_t(1) << 31;
  EXPECT_EQ(r->readAll(), (EventVector{ev(10, 20, 100, 1), ev(239, 179, 102, 0), ev(5, 6, o + 8, 1)}));
  const ReaderStats s = r->stats();
  EXPECT_EQ(s.invalid_events, 1u);
  EXPECT_EQ(s.other_words, 1u);
  EXPECT_EQ(s.unknown_words, 1u);
  EXPECT_EQ(s.out_of_range, 1u);
  EXPECT_FALSE(s.truncated);
}

TEST(FormatsAedat3, RoundTrip)
{
  std::mt19937_64 rng(5);
  EventVector ev;
  int64_t t = 0;
  for (int i = 0; i < 30000; ++i)
  {
    t += rng() % 1000 == 0 ? int64_t(rng() % 3000000000ull) : int64_t(rng() % 30);  // crosses 2^31 us
    ev.push_back(Event{t * 1000, uint16_t(rng() % 346), uint16_t(rng() % 260), bool(rng() & 1)});
  }
  ASSERT_GT(t, int64_t(1) << 32);
  TempFile f(".aedat");
  {
    formats::Aedat3Writer w(f.path(), "DAVIS346B", 1000);
    w.write(ev);
    w.close();
  }
  auto r = openEventFileReader(f.path());
  EXPECT_EQ(r->width(), 346u);
  EXPECT_EQ(r->height(), 260u);
  EXPECT_EQ(readInBatches(*r, 777), ev);
}

TEST(FormatsAedat3, TruncatedFileDeliversEveryCompleteEvent)
{
  Builder f;
  f.packet(1, 8, 0, 3, 3);
  f.polarity(1, 1, true, 10);
  f.polarity(2, 2, true, 11);
  const size_t damage = f.b.size();
  f.polarity(3, 3, true, 12);
  f.b.resize(f.b.size() - 3);  // cut inside the third event
  TempFile t(".aedat");
  t.write(f.b);
  auto r = openEventFileReader(t.path());
  EXPECT_EQ(r->readAll(), (EventVector{ev(1, 1, 10, 1), ev(2, 2, 11, 1)}));
  const ReaderStats s = r->stats();
  EXPECT_TRUE(s.truncated);
  EXPECT_EQ(s.truncated_offset, damage);
  EXPECT_EQ(s.truncated_bytes, 5u);
  ASSERT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings.back().find("byte " + std::to_string(damage)), std::string::npos);
}

TEST(FormatsAedat3, UnsupportedVersionAndFormatAreNamed)
{
  auto expectError = [](const std::string& header, const std::string& words) {
    Builder f(header);
    TempFile t(".aedat");
    t.write(f.b);
    try
    {
      openEventFileReader(t.path());
      ADD_FAILURE() << "accepted: " << header;
    }
    catch (const EventFormatError& e)
    {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  expectError("#!AER-DAT3.0\r\n#Format: RAW\r\n#Source 1: DVS128\r\n", "'3.0' is not supported");
  expectError("#!AER-DAT3.1\r\n#Format: SerializedTS\r\n#Source 1: DVS128\r\n#!END-HEADER\r\n",
              "'SerializedTS' is not supported");
  expectError("#!AER-DAT3.1\r\n#Format: RAW\r\n#Source 1: DVS128\r\n", "no #!END-HEADER");
}

TEST(FormatsAedat3, UnknownDeviceGivesUnknownSizeAndAWarning)
{
  Builder f("#!AER-DAT3.1\r\n#Format: RAW\r\n#Source 1: MysteryCam\r\n#!END-HEADER\r\n");
  f.packet(1, 8, 0, 1, 1);
  f.polarity(1000, 900, true, 5);
  TempFile t(".aedat");
  t.write(f.b);
  auto r = openEventFileReader(t.path());
  EXPECT_EQ(r->width(), 0u);
  EXPECT_EQ(r->readAll(), (EventVector{ev(1000, 900, 5, 1)}));
  ASSERT_FALSE(r->stats().warnings.empty());
  EXPECT_NE(r->stats().warnings[0].find("MysteryCam"), std::string::npos);
}

#include <dvs_driver/aedat_reader.h>

TEST(FormatsAedat2, OpenEventFileServesTheExistingAedat2Reader)
{
  // AEDAT 2.0 goes through aedat_reader.h (whole file), behind the same interface.
  const std::string path = std::string(DVS_REAL_DATA_DIR) + "/colleen_pen_short.aedat";
  EXPECT_EQ(detectEventFormat(path), EventFormat::Aedat2);
  const AedatRecording rec = readAedat(path);
  auto r = openEventFileReader(path);
  EXPECT_EQ(r->width(), rec.stream.width);
  EXPECT_EQ(r->height(), rec.stream.height);
  EXPECT_EQ(r->formatName(), "AEDAT 2.0 (" + rec.info.sensor_name + ")");
  EXPECT_EQ(readInBatches(*r, 10000), rec.stream.events);
  EXPECT_EQ(r->stats().events, rec.stream.events.size());
}
