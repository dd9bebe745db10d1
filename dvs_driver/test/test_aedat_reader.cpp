// AEDAT 2.0 reader on the real recordings in ../shared/data/real (read in place, never copied)
// and on malformed variants written to /tmp.
#include <dvs_driver/aedat_reader.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

using dvs_driver::AedatError;
using dvs_driver::readAedat;

namespace
{
const std::string kDataDir = DVS_REAL_DATA_DIR;

std::vector<uint8_t> fileBytes(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string errorOf(const std::vector<uint8_t>& bytes)
{
  try
  {
    readAedat(bytes.data(), bytes.size(), "memory.aedat");
  }
  catch (const AedatError& e)
  {
    return e.what();
  }
  return "";
}

double spanSeconds(const dvs_driver::EventVector& ev)
{
  return (ev.back().t_ns - ev.front().t_ns) * 1e-9;
}

void expectSortedAndInside(const dvs_driver::EventStream& s)
{
  for (size_t i = 0; i < s.events.size(); ++i)
  {
    ASSERT_LT(s.events[i].x, s.width) << i;
    ASSERT_LT(s.events[i].y, s.height) << i;
    if (i > 0)
      ASSERT_GE(s.events[i].t_ns, s.events[i - 1].t_ns) << i;
  }
}
}  // namespace

TEST(AedatReader, UcsdWalkingKnownAnswers)
{
  const auto rec = readAedat(kDataDir + "/ucsd_alex_walking_again.aedat");
  EXPECT_EQ(4612u, rec.info.data_offset);
  EXPECT_EQ("DVS128", rec.info.sensor_name);
  EXPECT_EQ(128u, rec.stream.width);
  EXPECT_EQ(128u, rec.stream.height);
  ASSERT_EQ(19182u, rec.stream.events.size());
  EXPECT_EQ(0u, rec.info.truncated_bytes);
  EXPECT_EQ(0u, rec.info.skippedRecords());
  // Event 0: raw 0x7683, t = 41306606 us -> x 62, row 9, OFF.
  const auto& e0 = rec.stream.events[0];
  EXPECT_EQ(41306606000LL, e0.t_ns);
  EXPECT_EQ(62, e0.x);
  EXPECT_EQ(9, e0.y);
  EXPECT_FALSE(e0.polarity);
  // Event 1: raw 0x615e, t = 41309379 -> x 80, row 30, ON.
  const auto& e1 = rec.stream.events[1];
  EXPECT_EQ(41309379000LL, e1.t_ns);
  EXPECT_EQ(80, e1.x);
  EXPECT_EQ(30, e1.y);
  EXPECT_TRUE(e1.polarity);
  EXPECT_NEAR(6.887, spanSeconds(rec.stream.events), 0.0005);
  expectSortedAndInside(rec.stream);
}

TEST(AedatReader, OtherDvs128RecordingsCountsAndSpans)
{
  struct Case
  {
    const char* file;
    size_t offset, events;
    double span;
  } cases[] = {{"colleen_pen_short.aedat", 3383, 130114, 6.181},
               {"biolab_caixa_box.aedat", 3412, 374039, 32.774}};
  for (const Case& c : cases)
  {
    const auto rec = readAedat(kDataDir + "/" + c.file);
    EXPECT_EQ(c.offset, rec.info.data_offset) << c.file;
    EXPECT_EQ("DVS128", rec.info.sensor_name) << c.file;
    ASSERT_EQ(c.events, rec.stream.events.size()) << c.file;
    EXPECT_NEAR(c.span, spanSeconds(rec.stream.events), 0.0005) << c.file;
    EXPECT_EQ(0u, rec.info.non_monotonic) << c.file;
    expectSortedAndInside(rec.stream);
  }
}

TEST(AedatReader, AllNegativeTimestampsAreKept)
{
  const auto rec = readAedat(kDataDir + "/biolab_dataset2_caixa_negative_ts.aedat");
  EXPECT_EQ(3412u, rec.info.data_offset);
  ASSERT_EQ(201523u, rec.stream.events.size());
  EXPECT_LT(rec.stream.events.front().t_ns, 0);
  EXPECT_LT(rec.stream.events.back().t_ns, 0);
  EXPECT_EQ(0u, rec.info.non_monotonic);
  EXPECT_EQ(0u, rec.info.timestamp_wraps);
  EXPECT_NEAR(18.492, spanSeconds(rec.stream.events), 0.0005);
  expectSortedAndInside(rec.stream);
}

TEST(AedatReader, Davis240DvsEventsSkippingImu)
{
  const auto rec = readAedat(kDataDir + "/IMU_rotDisk.aedat");
  EXPECT_EQ("DAVIS240", rec.info.sensor_name);
  EXPECT_EQ(240u, rec.stream.width);
  EXPECT_EQ(180u, rec.stream.height);
  EXPECT_EQ(425984u, rec.info.records);
  EXPECT_EQ(374296u, rec.stream.events.size());
  EXPECT_EQ(51688u, rec.info.imu_samples);
  EXPECT_EQ(0u, rec.info.aps_samples);
  EXPECT_EQ(51688u, rec.info.skippedRecords());
  expectSortedAndInside(rec.stream);
  // First DVS record 0x03c0b800 at 341678 us: y_up = 15 -> row 164, raw x 11 -> x 228, ON.
  EXPECT_EQ(341678000LL, rec.stream.events[0].t_ns);
  EXPECT_EQ(228, rec.stream.events[0].x);
  EXPECT_EQ(164, rec.stream.events[0].y);
  EXPECT_TRUE(rec.stream.events[0].polarity);
}

TEST(AedatReader, TruncatedFileIsToleratedAndReported)
{
  std::vector<uint8_t> bytes = fileBytes(kDataDir + "/IMU_rotDisk.aedat");
  ASSERT_FALSE(bytes.empty());
  bytes.resize(bytes.size() - 5);  // cut the last record mid-way
  const auto rec = readAedat(bytes.data(), bytes.size(), "cut.aedat");
  EXPECT_EQ(3u, rec.info.truncated_bytes);
  EXPECT_EQ(425983u, rec.info.records);
  EXPECT_EQ(374296u + 51688u - 1u, rec.stream.events.size() + rec.info.imu_samples);
}

TEST(AedatReader, HeaderOnlyFileHasNoEvents)
{
  std::vector<uint8_t> bytes = fileBytes(kDataDir + "/ucsd_alex_walking_again.aedat");
  bytes.resize(4612);
  const auto rec = readAedat(bytes.data(), bytes.size(), "header_only.aedat");
  EXPECT_EQ(0u, rec.stream.events.size());
  EXPECT_EQ(4612u, rec.info.data_offset);
  EXPECT_EQ(128u, rec.stream.width);
  EXPECT_EQ(0u, rec.info.truncated_bytes);
}

TEST(AedatReader, FirstDataByteHashIsData)
{
  // DAVIS240 record 0x2340200A = bytes "#@ \n": it even looks like a header line, but
  // `#End Of ASCII Header` has ended the header. y_up 141 -> row 38, raw x 2 -> x 237, OFF.
  const std::string header =
      "#!AER-DAT2.0\r\n# AEChip: eu.seebetter.ini.chips.davis.DAVIS240C\r\n#End Of ASCII Header\r\n";
  std::vector<uint8_t> bytes(header.begin(), header.end());
  const uint8_t rec1[8] = {0x23, 0x40, 0x20, 0x0A, 0x00, 0x00, 0x00, 0x10};
  bytes.insert(bytes.end(), rec1, rec1 + 8);
  auto r = readAedat(bytes.data(), bytes.size(), "m.aedat");
  EXPECT_EQ(header.size(), r.info.data_offset);
  ASSERT_EQ(1u, r.stream.events.size());
  EXPECT_EQ(237, r.stream.events[0].x);
  EXPECT_EQ(38, r.stream.events[0].y);
  EXPECT_FALSE(r.stream.events[0].polarity);
  EXPECT_EQ(16000, r.stream.events[0].t_ns);
  // Without the end line, a record starting with '#' followed by binary bytes is data too.
  const std::string header2 = "#!AER-DAT2.0\r\n# AEChip: DAVIS240C\r\n";
  std::vector<uint8_t> b2(header2.begin(), header2.end());
  const uint8_t rec2[16] = {0x23, 0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x10,  // y_up 140, x raw 1
                            0x00, 0x00, 0x18, 0x00, 0x00, 0x00, 0x00, 0x11};
  b2.insert(b2.end(), rec2, rec2 + 16);
  r = readAedat(b2.data(), b2.size(), "m2.aedat");
  EXPECT_EQ(header2.size(), r.info.data_offset);
  ASSERT_EQ(2u, r.stream.events.size());
  EXPECT_EQ(180 - 1 - 140, r.stream.events[0].y);
  EXPECT_EQ(238, r.stream.events[0].x);
  EXPECT_TRUE(r.stream.events[1].polarity);
  EXPECT_EQ(17000, r.stream.events[1].t_ns);
}

TEST(AedatReader, MalformedFilesGiveClearErrors)
{
  EXPECT_THROW(readAedat("/nonexistent/file.aedat"), AedatError);
  const auto str = [](const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); };
  EXPECT_NE(std::string::npos, errorOf(str("hello world")).find("not an AEDAT file"));
  EXPECT_NE(std::string::npos, errorOf({}).find("not an AEDAT file"));
  EXPECT_NE(std::string::npos, errorOf(str("#!AER-DAT3.1\r\n")).find("unsupported AEDAT version"));
  // Unknown chip and 32-bit addresses: cannot tell the sensor.
  std::vector<uint8_t> b = str("#!AER-DAT2.0\r\n# AEChip: something.Else\r\n#End Of ASCII Header\r\n");
  const uint8_t r[8] = {0x12, 0x34, 0x56, 0x78, 0, 0, 0, 1};
  b.insert(b.end(), r, r + 8);
  EXPECT_NE(std::string::npos, errorOf(b).find("cannot tell the sensor"));
}
