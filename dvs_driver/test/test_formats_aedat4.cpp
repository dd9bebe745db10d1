// AEDAT 4.0 reader and writer: the known answers of the real samples
// (../shared/data/formats/README.md), every compression through round trips, files without a
// data table, damaged and truncated files, unsupported versions and compressions.
#include "formats_test_util.h"

#include <dvs_driver/formats/aedat4.h>
#include <dvs_driver/formats/prophesee_raw.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

using namespace dvs_driver;
using namespace formats_test;
using formats::Aedat4Compression;

namespace
{
const std::string kDvx = "dvxplorer_320x240.aedat4";
const std::string kDavis = "davis346_346x260.aedat4";

EventVector randomEvents(size_t n, uint32_t w, uint32_t h, int64_t t0_us, unsigned seed)
{
  std::mt19937_64 rng(seed);
  EventVector ev;
  int64_t t = t0_us;
  for (size_t i = 0; i < n; ++i)
  {
    t += int64_t(rng() % 20);
    ev.push_back(Event{t * 1000, uint16_t(rng() % w), uint16_t(rng() % h), bool(rng() & 1)});
  }
  return ev;
}

void writeAedat4(const std::string& path, const EventVector& ev, uint32_t w, uint32_t h, Aedat4Compression c,
                 size_t per_packet = 1000)
{
  formats::Aedat4WriterOptions o;
  o.compression = c;
  o.events_per_packet = per_packet;
  formats::Aedat4Writer wr(path, w, h, o);
  wr.write(ev);
  wr.close();
}

// The dataTablePosition of a file written by Aedat4Writer sits at byte 14 + 32.
void setTablePosition(std::vector<uint8_t>& b, int64_t pos)
{
  std::memcpy(b.data() + 46, &pos, 8);
}

int64_t tablePosition(const std::vector<uint8_t>& b)
{
  int64_t p;
  std::memcpy(&p, b.data() + 46, 8);
  return p;
}
}  // namespace

TEST(FormatsAedat4, DvxplorerSampleKnownAnswers)
{
  auto r = openEventFileReader(sample(kDvx));
  EXPECT_EQ(r->formatName(), "AEDAT 4.0 (LZ4)");
  EXPECT_EQ(r->width(), 320u);
  EXPECT_EQ(r->height(), 240u);
  EXPECT_EQ(r->expectedEvents(), 111954);  // from the data table
  const EventVector events = r->readAll();
  const Summary s = summarize(events);
  EXPECT_EQ(s.n, 111954u);
  EXPECT_EQ(s.on, 55023u);
  EXPECT_EQ(s.n - s.on, 56931u);
  EXPECT_EQ(s.min_x, 0);
  EXPECT_EQ(s.max_x, 319);
  EXPECT_EQ(s.min_y, 0);
  EXPECT_EQ(s.max_y, 239);
  EXPECT_EQ(events.front(), ev(154, 204, 1605537493718345, 0));
  EXPECT_EQ(events.back(), ev(88, 237, 1605537494308262, 1));
  EXPECT_EQ(events.back().t_ns - events.front().t_ns, 589917000);
  for (size_t i = 1; i < events.size(); ++i)
    ASSERT_LE(events[i - 1].t_ns, events[i].t_ns) << i;
  const ReaderStats st = r->stats();
  EXPECT_EQ(st.other_words, 59u);  // the IMUS packets
  EXPECT_EQ(st.unknown_words, 0u);
  EXPECT_EQ(st.damaged_packets, 0u);
  EXPECT_FALSE(st.truncated);
}

TEST(FormatsAedat4, Davis346SampleKnownAnswers)
{
  auto r = openEventFileReader(sample(kDavis));
  EXPECT_EQ(r->width(), 346u);
  EXPECT_EQ(r->height(), 260u);
  EXPECT_EQ(r->expectedEvents(), 117667);
  const EventVector events = r->readAll();
  const Summary s = summarize(events);
  EXPECT_EQ(s.n, 117667u);
  EXPECT_EQ(s.on, 72363u);
  EXPECT_EQ(s.n - s.on, 45304u);
  EXPECT_EQ(s.min_x, 0);
  EXPECT_EQ(s.max_x, 345);
  EXPECT_EQ(s.min_y, 0);
  EXPECT_EQ(s.max_y, 259);
  EXPECT_EQ(events.front(), ev(218, 15, 1633953690975950, 1));
  EXPECT_EQ(events.back(), ev(137, 56, 1633953691105949, 0));
  EXPECT_EQ(events.back().t_ns - events.front().t_ns, 129999000);
  EXPECT_EQ(r->stats().other_words, 3u + 13u + 11u);  // FRME, IMUS, TRIG packets
}

TEST(FormatsAedat4, ScanWithoutTheDataTableGivesTheSameEvents)
{
  // A copy whose dataTablePosition says "none" (-1): the packets are scanned (and the table
  // bytes at the end are then read as a truncated packet).
  std::vector<uint8_t> b = readBytes(sample(kDvx));
  const EventVector all = openEventFileReader(sample(kDvx))->readAll();
  // The sample's IOHeader: field 1 (dataTablePosition) of the root table, found by hand.
  int64_t want = 945243;
  size_t at = 0;
  for (size_t i = 18; i + 8 < 18 + 2316; ++i)
    if (std::memcmp(b.data() + i, &want, 8) == 0)
      at = i;
  ASSERT_NE(at, 0u);
  const int64_t none = -1;
  std::memcpy(b.data() + at, &none, 8);
  b.resize(945243);  // drop the table: an interrupted recording
  TempFile f(".aedat4");
  f.write(b);
  auto r = openEventFileReader(f.path());
  EXPECT_EQ(r->expectedEvents(), -1);
  EXPECT_EQ(r->readAll(), all);
  EXPECT_FALSE(r->stats().truncated);
  EXPECT_EQ(r->stats().other_words, 59u);
}

TEST(FormatsAedat4, TruncatedSampleDeliversEveryCompletePacket)
{
  // Cut the sample in the middle of its packets (the data table is lost with the tail).
  const std::vector<uint8_t> b = readBytes(sample(kDvx));
  const EventVector all = openEventFileReader(sample(kDvx))->readAll();
  const size_t cut = 500000;
  TempFile f(".aedat4");
  f.write(b.data(), cut);
  auto r = openEventFileReader(f.path());
  const EventVector part = r->readAll();
  ASSERT_GT(part.size(), 10000u);
  ASSERT_LT(part.size(), all.size());
  EXPECT_TRUE(std::equal(part.begin(), part.end(), all.begin()));
  const ReaderStats s = r->stats();
  EXPECT_TRUE(s.truncated);
  EXPECT_GT(s.truncated_offset, 2334u);
  EXPECT_LT(s.truncated_offset, cut);
  EXPECT_EQ(s.truncated_offset + s.truncated_bytes, cut);
  bool named = false;
  for (const auto& w : s.warnings)
    named |= w.find("byte " + std::to_string(s.truncated_offset)) != std::string::npos;
  EXPECT_TRUE(named);
  // Every packet before the damage was delivered: the next packet header is the damaged one.
  const uint8_t* h = b.data() + s.truncated_offset;
  int32_t size;
  std::memcpy(&size, h + 4, 4);
  EXPECT_GT(s.truncated_offset + 8 + uint64_t(size), cut);
}

TEST(FormatsAedat4, RoundTripEveryCompression)
{
  const EventVector ev = randomEvents(25000, 346, 260, 1633953690975950, 11);
  for (auto c : {Aedat4Compression::None, Aedat4Compression::Lz4, Aedat4Compression::Lz4High,
                 Aedat4Compression::Zstd, Aedat4Compression::ZstdHigh})
  {
    TempFile f(".aedat4");
    writeAedat4(f.path(), ev, 346, 260, c, 4096);
    auto r = openEventFileReader(f.path());
    EXPECT_EQ(r->formatName(), std::string("AEDAT 4.0 (") + formats::aedat4CompressionName(c) + ")");
    EXPECT_EQ(r->width(), 346u);
    EXPECT_EQ(r->height(), 260u);
    EXPECT_EQ(r->expectedEvents(), 25000);
    EXPECT_EQ(readInBatches(*r, 3000), ev) << formats::aedat4CompressionName(c);
    EXPECT_EQ(r->stats().damaged_packets, 0u);
    // The same without the data table (scan).
    std::vector<uint8_t> b = readBytes(f.path());
    const int64_t table = tablePosition(b);
    setTablePosition(b, -1);
    b.resize(size_t(table));
    TempFile g(".aedat4");
    g.write(b);
    EXPECT_EQ(openEventFileReader(g.path())->readAll(), ev) << formats::aedat4CompressionName(c) << " without table";
  }
}

TEST(FormatsAedat4, RoundTripOfTheRealSamplesThroughBothWriters)
{
  for (const std::string& name : {kDvx, kDavis})
  {
    auto in = openEventFileReader(sample(name));
    const EventVector all = in->readAll();
    TempFile a(".aedat4"), raw(".raw");
    writeAedat4(a.path(), all, in->width(), in->height(), Aedat4Compression::Lz4, 10000);
    EXPECT_EQ(openEventFileReader(a.path())->readAll(), all) << name;
    formats::Evt3Writer w(raw.path(), in->width(), in->height());  // epoch times: offset key
    w.write(all);
    w.close();
    auto r = openEventFileReader(raw.path());
    EXPECT_EQ(r->width(), in->width());
    EXPECT_EQ(r->readAll(), all) << name << " via EVT 3.0";
  }
}

TEST(FormatsAedat4, EmptyFileHasNoEvents)
{
  TempFile f(".aedat4");
  writeAedat4(f.path(), {}, 128, 128, Aedat4Compression::Lz4);
  auto r = openEventFileReader(f.path());
  EventVector out;
  EXPECT_FALSE(r->read(out, 100));
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(r->expectedEvents(), 0);
}

TEST(FormatsAedat4, UnsupportedVersionAndCompressionAreNamed)
{
  TempFile f(".aedat4");
  writeAedat4(f.path(), randomEvents(10, 64, 64, 0, 1), 64, 64, Aedat4Compression::None);
  std::vector<uint8_t> b = readBytes(f.path());
  std::vector<uint8_t> c = b;
  const int32_t seven = 7;
  std::memcpy(c.data() + 14 + 28, &seven, 4);  // IOHeader compression field
  TempFile g(".aedat4");
  g.write(c);
  try
  {
    openEventFileReader(g.path());
    FAIL() << "compression 7 accepted";
  }
  catch (const EventFormatError& e)
  {
    EXPECT_NE(std::string(e.what()).find("compression 7 is not supported"), std::string::npos) << e.what();
  }
  c = b;
  c[11] = '5';  // #!AER-DAT4.5
  g.write(c);
  try
  {
    openEventFileReader(g.path());
    FAIL() << "version 4.5 accepted";
  }
  catch (const EventFormatError& e)
  {
    EXPECT_NE(std::string(e.what()).find("AER-DAT4.5"), std::string::npos) << e.what();
  }
}

TEST(FormatsAedat4, DamagedAndUnknownPacketsAreSkippedAndCounted)
{
  const EventVector ev = randomEvents(3000, 100, 100, 5000, 2);
  TempFile f(".aedat4");
  writeAedat4(f.path(), ev, 100, 100, Aedat4Compression::Lz4, 1000);  // 3 packets
  std::vector<uint8_t> b = readBytes(f.path());
  const int64_t table = tablePosition(b);
  // Scan mode, and insert a packet of an unknown stream (id 9) before the first packet.
  setTablePosition(b, -1);
  b.resize(size_t(table));
  uint32_t n;
  std::memcpy(&n, b.data() + 14, 4);
  const size_t first_packet = 18 + n;
  const std::vector<uint8_t> unknown = {9, 0, 0, 0, 4, 0, 0, 0, 1, 2, 3, 4};
  b.insert(b.begin() + long(first_packet), unknown.begin(), unknown.end());
  // Damage the LZ4 frame magic of the (now) first event packet.
  const size_t p1 = first_packet + unknown.size();
  b[p1 + 8] ^= 0xFF;
  TempFile g(".aedat4");
  g.write(b);
  auto r = openEventFileReader(g.path());
  const EventVector got = r->readAll();
  EXPECT_EQ(got, EventVector(ev.begin() + 1000, ev.end()));
  const ReaderStats s = r->stats();
  EXPECT_EQ(s.unknown_words, 1u);
  EXPECT_EQ(s.damaged_packets, 1u);
  EXPECT_FALSE(s.truncated);
}

TEST(FormatsAedat4, ImuSamplesOfTheRealSamples)
{
  // The samples README gives the IMUS packets (dvxplorer 59, davis346 13); the sample counts and
  // the first / last samples come from a separate decode of those packets (a Python script with
  // the lz4 command-line tool, written from the reference's layout, not this reader): 475 and 130
  // samples. Units: the file's g and deg/s become m/s^2 and rad/s. Physics: a camera at rest-ish
  // sees about 1 g and small rotation rates.
  struct Case
  {
    std::string name;
    size_t samples;
    int64_t first_t_us, last_t_us;
    double first_ax_g, last_ax_g;
  } cases[] = {{kDvx, 475, 1605537493718788, 1605537494307448, 0.1263427734375, 0.1251220703125},
               {kDavis, 130, 1633953690976628, 1633953691105605, -0.0604248046875, -0.0623779296875}};
  for (const auto& c : cases)
  {
    auto r = openEventFileReader(sample(c.name));
    std::vector<ImuSample> imu;
    EventVector batch, all;
    size_t most_kept = 0;
    while (r->read(batch, 10000))
    {
      all.insert(all.end(), batch.begin(), batch.end());
      batch.clear();
      most_kept = std::max(most_kept, r->takeImu(imu));
    }
    r->takeImu(imu);
    ASSERT_EQ(imu.size(), c.samples) << c.name;
    EXPECT_LT(most_kept, c.samples) << c.name;  // delivered while reading, not held to the end
    EXPECT_EQ(r->stats().imu_samples, c.samples);
    EXPECT_EQ(imu.front().t_ns, c.first_t_us * 1000) << c.name;
    EXPECT_EQ(imu.back().t_ns, c.last_t_us * 1000) << c.name;
    EXPECT_DOUBLE_EQ(imu.front().accel[0], c.first_ax_g * kStandardGravity) << c.name;
    EXPECT_DOUBLE_EQ(imu.back().accel[0], c.last_ax_g * kStandardGravity) << c.name;
    for (size_t i = 0; i < imu.size(); ++i)
    {
      const ImuSample& s = imu[i];
      if (i > 0)
        EXPECT_GE(s.t_ns, imu[i - 1].t_ns);
      EXPECT_GE(s.t_ns, all.front().t_ns - 2000000);
      EXPECT_LE(s.t_ns, all.back().t_ns + 2000000);
      const double g = std::sqrt(s.accel[0] * s.accel[0] + s.accel[1] * s.accel[1] + s.accel[2] * s.accel[2]);
      EXPECT_GT(g, 9.0) << c.name << " sample " << i;
      EXPECT_LT(g, 11.5) << c.name << " sample " << i;
      for (double w : s.gyro)
        EXPECT_LT(std::abs(w), 1.0);  // rad/s
      EXPECT_GT(s.temperature_c, 10.0);
      EXPECT_LT(s.temperature_c, 60.0);
    }
  }
}

TEST(Aedat4Reader, TimesBeyondInt64NanosecondsAreSkippedAndCounted)
{
  // Found by fuzzing: a corrupt packet's time of 7e16 us overflowed int64 nanoseconds (UB).
  const int64_t marker_us = 123456789012345;  // a unique byte pattern to find in the file
  EventVector ev = {Event{marker_us * 1000, 1, 2, true}, Event{(marker_us + 1) * 1000, 3, 4, false},
                    Event{(marker_us + 2) * 1000, 5, 6, true}};
  TempFile f(".aedat4");
  formats::Aedat4WriterOptions o;
  o.compression = Aedat4Compression::None;
  {
    formats::Aedat4Writer w(f.path(), 128, 128, o);
    w.write(ev);
    w.close();
  }
  std::ifstream in(f.path(), std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  uint8_t pattern[8];
  std::memcpy(pattern, &marker_us, 8);  // little endian, as the file stores it
  auto at = std::search(bytes.begin(), bytes.end(), pattern, pattern + 8);
  ASSERT_NE(at, bytes.end());
  const int64_t corrupt = int64_t(1) << 56;  // 7.2e16 us
  std::memcpy(&*at, &corrupt, 8);
  f.write(bytes);
  auto r = openEventFileReader(f.path());
  const EventVector back = r->readAll();
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0], ev[1]);
  EXPECT_EQ(r->stats().invalid_events, 1u);
}

TEST(FormatsAedat2, ImuThroughTheFormatReaderInterface)
{
  // The AEDAT 2.0 DAVIS240 recording's IMU6 records (51,688 = 7,384 samples of 7) come out of
  // openEventFileReader's takeImu as they do from aedat_reader.h.
  auto r = openEventFileReader(std::string(DVS_REAL_DATA_DIR) + "/IMU_rotDisk.aedat");
  r->readAll();
  std::vector<ImuSample> imu;
  EXPECT_EQ(7384u, r->takeImu(imu));
  EXPECT_EQ(7384u, r->stats().imu_samples);
  EXPECT_EQ(342081000LL, imu.front().t_ns);
  EXPECT_EQ(0u, r->takeImu(imu));
}
