// AEDAT 2.0 reader on the real recordings in ../shared/data/real (read in place, never copied)
// and on malformed variants written to /tmp.
#include <dvs_driver/aedat_reader.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

// ---- DAVIS IMU samples (7 records each) ----
namespace
{
// A DAVIS240 AEDAT 2.0 file in memory: header (with `extra` header lines) and records.
std::vector<uint8_t> davisFile(const std::vector<std::pair<uint32_t, int32_t>>& records, const std::string& extra = "")
{
  const std::string header = "#!AER-DAT2.0\r\n# AEChip: eu.seebetter.ini.chips.davis.DAVIS240C\r\n" + extra +
                             "#End Of ASCII Header\r\n";
  std::vector<uint8_t> b(header.begin(), header.end());
  for (const auto& r : records)
    for (uint32_t v : {r.first, static_cast<uint32_t>(r.second)})
      for (int k = 3; k >= 0; --k)
        b.push_back(static_cast<uint8_t>(v >> (8 * k)));
  return b;
}

uint32_t imuAddress(int code, int16_t value)
{
  return 0x80000C00u | (static_cast<uint32_t>(code) << 28) | (static_cast<uint32_t>(static_cast<uint16_t>(value)) << 12);
}

void addImuSample(std::vector<std::pair<uint32_t, int32_t>>& r, int32_t t, const int16_t v[7])
{
  for (int c = 0; c < 7; ++c)
    r.push_back({imuAddress(c, v[c]), t});
}
}  // namespace

TEST(AedatReader, Davis240ImuSamplesOfTheRealFile)
{
  const auto rec = readAedat(kDataDir + "/IMU_rotDisk.aedat");
  // 51,688 IMU records (the data README) = 7,384 samples of 7; none incomplete.
  EXPECT_EQ(51688u / 7u, rec.info.imu_decoded);
  ASSERT_EQ(7384u, rec.imu.size());
  EXPECT_EQ(0u, rec.info.imu_dropped);
  // The header's jAER preferences: ImuAccelScaleG8, GyroFullScaleDegPerSec1000.
  EXPECT_TRUE(rec.info.imu_scale_from_header);
  EXPECT_EQ(8.0, rec.info.imu_accel_full_scale_g);
  EXPECT_EQ(1000.0, rec.info.imu_gyro_full_scale_deg_s);
  // First sample (records at 342081 us): raw ax 948, ay -4042, az 426, temperature -1184,
  // gx -115, gy 20, gz 1040; 4096 LSB/g, 32.8 LSB/(deg/s), T = raw/340 + 35.
  const dvs_driver::ImuSample& s = rec.imu[0];
  EXPECT_EQ(342081000LL, s.t_ns);
  const double g = dvs_driver::kStandardGravity, deg = M_PI / 180.0;
  EXPECT_DOUBLE_EQ(948 / 4096.0 * g, s.accel[0]);
  EXPECT_DOUBLE_EQ(-4042 / 4096.0 * g, s.accel[1]);
  EXPECT_DOUBLE_EQ(426 / 4096.0 * g, s.accel[2]);
  EXPECT_DOUBLE_EQ(-115 / 32.8 * deg, s.gyro[0]);
  EXPECT_DOUBLE_EQ(20 / 32.8 * deg, s.gyro[1]);
  EXPECT_DOUBLE_EQ(1040 / 32.8 * deg, s.gyro[2]);
  EXPECT_NEAR(-1184 / 340.0 + 35.0, s.temperature_c, 1e-12);
  // Physics: gravity's magnitude at every sample (a hand-held camera: within 0.8..1.25 g), a
  // ~2.5 kHz IMU (406 us median interval), times increasing, within the events' span.
  std::vector<int64_t> dt;
  for (size_t i = 0; i < rec.imu.size(); ++i)
  {
    const auto& a = rec.imu[i].accel;
    const double n = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) / g;
    ASSERT_GT(n, 0.8) << i;
    ASSERT_LT(n, 1.25) << i;
    if (i > 0)
    {
      ASSERT_GT(rec.imu[i].t_ns, rec.imu[i - 1].t_ns) << i;
      dt.push_back(rec.imu[i].t_ns - rec.imu[i - 1].t_ns);
    }
  }
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  EXPECT_EQ(406000, dt[dt.size() / 2]);
  EXPECT_EQ(3508347000LL, rec.imu.back().t_ns);
}

TEST(AedatReader, Davis240ImuStreamedEqualsWholeFile)
{
  const std::string path = kDataDir + "/IMU_rotDisk.aedat";
  const auto whole = readAedat(path);
  dvs_driver::AedatFileSource src(path);
  dvs_driver::EventVector events;
  dvs_driver::ImuVector imu;
  size_t max_kept = 0;
  while (src.read(events, 4096) > 0)
  {
    dvs_driver::ImuVector part;
    max_kept = std::max(max_kept, src.takeImu(part));
    imu.insert(imu.end(), part.begin(), part.end());
    events.clear();
  }
  src.takeImu(imu);
  EXPECT_EQ(whole.imu, imu);
  EXPECT_LT(max_kept, 1000u);  // taken piece by piece, not held to the end
  EXPECT_EQ(7384u, src.aedatInfo().imu_decoded);
  src.rewind();
  EXPECT_EQ(0u, src.takeImu(imu));
}

TEST(AedatReader, ImuSamplesKnownAnswersAndBrokenSamplesDropped)
{
  const int16_t a[7] = {8192, -8192, 16384, 340, 655, -655, 131};  // 1 g, -1 g, 2 g, 36 C, ...
  std::vector<std::pair<uint32_t, int32_t>> r;
  addImuSample(r, 100, a);
  r.push_back({0x03c0b800u, 150});  // a DVS event between IMU samples
  // An incomplete sample (codes 0-3 only) then a complete one: the first 4 records are dropped.
  for (int c = 0; c < 4; ++c)
    r.push_back({imuAddress(c, 1), 200});
  addImuSample(r, 300, a);
  // A sample whose records disagree on the time: dropped (7 records), and a stray code 5.
  for (int c = 0; c < 7; ++c)
    r.push_back({imuAddress(c, 1), c < 3 ? 400 : 401});
  r.push_back({imuAddress(5, 1), 500});
  addImuSample(r, 600, a);
  r.push_back({imuAddress(0, 1), 700});  // an incomplete sample at the end
  const auto bytes = davisFile(r);
  const auto rec = readAedat(bytes.data(), bytes.size(), "imu.aedat");
  EXPECT_EQ(1u, rec.stream.events.size());
  EXPECT_EQ(r.size() - 1, rec.info.imu_samples);
  ASSERT_EQ(3u, rec.imu.size());
  EXPECT_EQ(3u, rec.info.imu_decoded);
  EXPECT_EQ(4u + 7u + 1u + 1u, rec.info.imu_dropped);
  // No scale in the header: jAER's defaults, 4 g (8192 LSB/g) and 500 deg/s (65.5 LSB/(deg/s)).
  EXPECT_FALSE(rec.info.imu_scale_from_header);
  const double g = dvs_driver::kStandardGravity, deg = M_PI / 180.0;
  EXPECT_EQ(100000, rec.imu[0].t_ns);
  EXPECT_EQ(300000, rec.imu[1].t_ns);
  EXPECT_EQ(600000, rec.imu[2].t_ns);
  for (const auto& s : rec.imu)
  {
    EXPECT_DOUBLE_EQ(g, s.accel[0]);
    EXPECT_DOUBLE_EQ(-g, s.accel[1]);
    EXPECT_DOUBLE_EQ(2 * g, s.accel[2]);
    EXPECT_DOUBLE_EQ(10 * deg, s.gyro[0]);
    EXPECT_DOUBLE_EQ(-10 * deg, s.gyro[1]);
    EXPECT_DOUBLE_EQ(131 / 65.5 * deg, s.gyro[2]);
    EXPECT_DOUBLE_EQ(36.0, s.temperature_c);
  }
}

TEST(AedatReader, ImuFullScaleFromTheHeader)
{
  const int16_t a[7] = {4096, 0, 0, 0, 164, 0, 0};
  std::vector<std::pair<uint32_t, int32_t>> r;
  addImuSample(r, 1, a);
  const double g = dvs_driver::kStandardGravity, deg = M_PI / 180.0;
  // The MPU registers only: ACCEL_CONFIG 24 (AFS_SEL 3: 16 g, 2048 LSB/g), GYRO_CONFIG 0 (250 deg/s).
  auto bytes = davisFile(r, "#    <entry key=\"CPLDByte.imu4_ACCEL_CONFIG\" value=\"24\"/>\r\n"
                            "#    <entry key=\"CPLDByte.imu3_GYRO_CONFIG\" value=\"0\"/>\r\n");
  auto rec = readAedat(bytes.data(), bytes.size(), "regs.aedat");
  ASSERT_EQ(1u, rec.imu.size());
  EXPECT_TRUE(rec.info.imu_scale_from_header);
  EXPECT_DOUBLE_EQ(2 * g, rec.imu[0].accel[0]);
  EXPECT_DOUBLE_EQ(164 / 131.0 * deg, rec.imu[0].gyro[0]);
  // The named settings win over the registers, whichever comes first.
  bytes = davisFile(r, "#    <entry key=\"ImuAccelScale\" value=\"ImuAccelScaleG2\"/>\r\n"
                       "#    <entry key=\"CPLDByte.imu4_ACCEL_CONFIG\" value=\"24\"/>\r\n"
                       "#    <entry key=\"ImuGyroScale\" value=\"GyroFullScaleDegPerSec2000\"/>\r\n");
  rec = readAedat(bytes.data(), bytes.size(), "named.aedat");
  ASSERT_EQ(1u, rec.imu.size());
  EXPECT_DOUBLE_EQ(0.25 * g, rec.imu[0].accel[0]);
  EXPECT_DOUBLE_EQ(164 / 16.4 * deg, rec.imu[0].gyro[0]);
}

TEST(AedatReader, Dvs128FilesHaveNoImu)
{
  const auto rec = readAedat(kDataDir + "/ucsd_alex_walking_again.aedat");
  EXPECT_TRUE(rec.imu.empty());
  EXPECT_EQ(0u, rec.info.imu_decoded);
}
