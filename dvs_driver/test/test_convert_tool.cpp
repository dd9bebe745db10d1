// Runs the real `convert` executable on the real recordings and checks its JSON line and outputs.
#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/recording.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/imu_msg.h>
#include <dvs_driver/imu_text_io.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdio>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

namespace
{
const std::string kData = DVS_REAL_DATA_DIR;
const std::string kTool = CONVERT_TOOL;

struct ToolRun
{
  int status;
  std::string out;
};

ToolRun run(const std::string& args)
{
  const std::string cmd = kTool + " " + args + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  ToolRun r{-1, ""};
  std::array<char, 4096> buf;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0)
    r.out.append(buf.data(), n);
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

std::string tmp(const std::string& name)
{
  return "/tmp/dvs_convert_test_" + std::to_string(::getpid()) + "_" + name;
}
}  // namespace

TEST(ConvertTool, AedatToTextSummaryAndContent)
{
  const std::string out = tmp("walk.txt");
  const ToolRun r = run("--input " + kData + "/ucsd_alex_walking_again.aedat --output " + out);
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"events\":19182,")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"span_s\":6.886550,")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"width\":128,\"height\":128,\"sensor\":\"DVS128\",\"skipped_words\":0"))
      << r.out;
  EXPECT_EQ(1, std::count(r.out.begin(), r.out.end(), '\n'));  // one line
  const auto events = dvs_driver::readEventsText(out);
  const auto ref = dvs_driver::readAedat(kData + "/ucsd_alex_walking_again.aedat");
  ASSERT_EQ(ref.stream.events.size(), events.size());
  for (size_t i = 0; i < events.size(); ++i)
    ASSERT_EQ(ref.stream.events[i], events[i]) << i;
  std::remove(out.c_str());
}

TEST(ConvertTool, DavisToBagIn1msPacketsAndBack)
{
  const std::string bag = tmp("disk.bag");
  const ToolRun r = run("--input " + kData + "/IMU_rotDisk.aedat --output " + bag);
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"events\":374296,")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"width\":240,\"height\":180,\"sensor\":\"DAVIS240\",\"skipped_words\":51688"))
      << r.out;
  const auto s = dvs_driver::readEventsBag(bag, "/dvs/events");
  const auto ref = dvs_driver::readAedat(kData + "/IMU_rotDisk.aedat");
  EXPECT_EQ(240u, s.width);
  ASSERT_EQ(ref.stream.events.size(), s.events.size());
  EXPECT_EQ(ref.stream.events.front(), s.events.front());
  EXPECT_EQ(ref.stream.events.back(), s.events.back());

  // Bag back to text: same events.
  const std::string txt = tmp("disk.txt");
  const ToolRun r2 = run("--input " + bag + " --output " + txt);
  ASSERT_EQ(0, r2.status) << r2.out;
  EXPECT_NE(std::string::npos, r2.out.find("\"events\":374296,")) << r2.out;
  EXPECT_EQ(374296u, dvs_driver::readEventsText(txt).size());
  std::remove(bag.c_str());
  std::remove(txt.c_str());
}

TEST(ConvertTool, PacketPeriodInSecondsAndTheDeprecatedMilliseconds)
{
  // 5 ms packets: the packet count is the number of distinct 5 ms periods of the events.
  const std::string in = kData + "/ucsd_alex_walking_again.aedat";
  const auto ref = dvs_driver::readAedat(in);
  size_t expected = 0;
  int64_t last = -1;
  for (const auto& e : ref.stream.events)
    if (e.t_ns / 5000000 != last)
    {
      ++expected;
      last = e.t_ns / 5000000;
    }
  const std::string bag = tmp("p5.bag");
  const ToolRun s = run("--input " + in + " --output " + bag + " --packet-period 0.005");
  ASSERT_EQ(0, s.status) << s.out;
  EXPECT_NE(std::string::npos, s.out.find("\"packets\":" + std::to_string(expected) + ",")) << s.out;
  const ToolRun ms = run("--input " + in + " --output " + bag + " --packet-period-ms 5");
  ASSERT_EQ(0, ms.status) << ms.out;
  EXPECT_NE(std::string::npos, ms.out.find("--packet-period-ms is deprecated: use --packet-period 0.005")) << ms.out;
  EXPECT_NE(std::string::npos, ms.out.find("\"packets\":" + std::to_string(expected) + ",")) << ms.out;
  std::remove(bag.c_str());
}

TEST(ConvertTool, NegativeTimesNeedZeroTimeForBags)
{
  const std::string bag = tmp("neg.bag");
  const std::string in = kData + "/biolab_dataset2_caixa_negative_ts.aedat";
  const ToolRun bad = run("--input " + in + " --output " + bag);
  EXPECT_EQ(1, bad.status);
  EXPECT_NE(std::string::npos, bad.out.find("--zero-time")) << bad.out;
  const ToolRun ok = run("--input " + in + " --output " + bag + " --zero-time");
  ASSERT_EQ(0, ok.status) << ok.out;
  EXPECT_NE(std::string::npos, ok.out.find("\"events\":201523,")) << ok.out;
  const auto s = dvs_driver::readEventsBag(bag);
  ASSERT_EQ(201523u, s.events.size());
  EXPECT_EQ(0, s.events.front().t_ns);
  std::remove(bag.c_str());
}

TEST(ConvertTool, TextInputInfersSensorAndBadUsageFails)
{
  const std::string txt = tmp("small.txt");
  {
    FILE* f = std::fopen(txt.c_str(), "w");
    std::fputs("0.001 10 20 1\n0.0025 239 5 0\n", f);
    std::fclose(f);
  }
  const std::string bag = tmp("small.bag");
  const ToolRun r = run("--input " + txt + " --output " + bag);
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"events\":2,\"span_s\":0.001500,\"width\":240,\"height\":180")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"packets\":2")) << r.out;
  EXPECT_EQ(2, run("--input " + txt).status);
  EXPECT_EQ(2, run("--bogus").status);
  const ToolRun missing = run("--input /nonexistent.aedat --output " + bag);
  EXPECT_EQ(1, missing.status);
  EXPECT_NE(std::string::npos, missing.out.find("/nonexistent.aedat")) << missing.out;
  std::remove(txt.c_str());
  std::remove(bag.c_str());
}

// ---- Bad input and faults (issue 19): named errors, non-zero exit, no abort, counters ----
namespace
{
std::string fullLink(const std::string& name)
{
  const std::string p = tmp(name);
  ::unlink(p.c_str());
  EXPECT_EQ(0, ::symlink("/dev/full", p.c_str()));
  return p;
}

void writeBytes(const std::string& path, const std::string& bytes)
{
  FILE* f = std::fopen(path.c_str(), "wb");
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
}

// AEDAT 2.0 with a DVS128 header and records {address, time in us}.
std::string aedat(const std::vector<std::pair<uint32_t, int32_t>>& records)
{
  std::string b = "#!AER-DAT2.0\r\n# AEChip: ch.unizh.ini.jaer.chip.retina.DVS128\r\n";
  for (const auto& r : records)
    for (const uint32_t v : {r.first, static_cast<uint32_t>(r.second)})
      for (int shift = 24; shift >= 0; shift -= 8)
        b.push_back(static_cast<char>((v >> shift) & 0xFF));
  return b;
}
}  // namespace

TEST(ConvertTool, FullDiskAndMissingFolderAreNamedErrorsNotAborts)
{
  const std::string in = kData + "/ucsd_alex_walking_again.aedat";
  for (const std::string name : {"full.txt", "full.bag"})
  {
    const std::string out = fullLink(name);
    const ToolRun r = run("--input " + in + " --output " + out);
    EXPECT_EQ(1, r.status) << r.out;  // an abort would be -1 (signal)
    EXPECT_NE(std::string::npos, r.out.find("convert: " + out + ": write failed: No space left on device")) << r.out;
    EXPECT_EQ(std::string::npos, r.out.find("\"events\"")) << r.out;  // no success line
    std::remove(out.c_str());
  }
  // rosbag's own file on a full disk (its temporary file is the link).
  const std::string bag = tmp("rosbag_full.bag");
  const std::string link = fullLink("rosbag_full.bag.tmp");
  const ToolRun b = run("--input " + in + " --output " + bag);
  EXPECT_EQ(1, b.status) << b.out;
  EXPECT_NE(std::string::npos, b.out.find("convert: " + bag + ": cannot create the bag: Error writing to file")) << b.out;
  std::remove(link.c_str());
  for (const std::string name : {"/no/such/folder/x.txt", "/no/such/folder/x.bag"})
  {
    const ToolRun m = run("--input " + in + " --output " + tmp("") + name);
    EXPECT_EQ(1, m.status) << m.out;
    EXPECT_NE(std::string::npos, m.out.find(tmp("") + name + ": cannot create the ")) << m.out;
    EXPECT_NE(std::string::npos, m.out.find("does not exist")) << m.out;
  }
}

TEST(ConvertTool, JsonHasTheInputChecks)
{
  const std::string out = tmp("walk_checks.txt");
  const ToolRun r = run("--input " + kData + "/ucsd_alex_walking_again.aedat --output " + out);
  ASSERT_EQ(0, r.status) << r.out;
  // The recording holds 27 exact duplicates (0.14%: normal for a DVS128, no warning).
  EXPECT_NE(std::string::npos,
            r.out.find("\"records\":19182,\"skipped\":{\"sync\":0,\"aps\":0,\"imu\":0,\"out_of_range\":0},"
                       "\"outside_sensor\":0,\"backwards\":0,\"max_backwards_s\":0.000000000,\"clamped\":0,"
                       "\"duplicates\":27,\"imu_samples\":0}"))
      << r.out;
  EXPECT_EQ(std::string::npos, r.out.find("warning")) << r.out;
  std::remove(out.c_str());
}

TEST(ConvertTool, AedatBackwardsTimesAreCountedAndReported)
{
  auto addr = [](uint32_t x, uint32_t y) { return ((127 - y) << 8) | ((127 - x) << 1); };
  const std::string in = tmp("back.aedat");
  writeBytes(in, aedat({{addr(1, 1), 10}, {addr(2, 1), 20}, {addr(3, 1), 5}, {addr(4, 1), 6}, {addr(5, 1), 30}}));
  const std::string out = tmp("back.txt");
  const ToolRun r = run("--input " + in + " --output " + out);
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"events\":5,")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"backwards\":1,\"max_backwards_s\":0.000015000,\"clamped\":2,")) << r.out;
  EXPECT_NE(std::string::npos,
            r.out.find("convert: warning: " + in + ": 1 time stamp going backwards (by up to 1.5e-05 s), "
                       "2 event times clamped to the time before them"))
      << r.out;
  std::remove(in.c_str());
  std::remove(out.c_str());
}

TEST(ConvertTool, GarbageAedatNamesWhatWasSkipped)
{
  std::vector<std::pair<uint32_t, int32_t>> records;
  uint32_t x = 12345;
  for (int i = 0; i < 1000; ++i)
  {
    x = x * 1103515245u + 12345u;
    records.emplace_back(x | 0x10000u, static_cast<int32_t>(x >> 3));  // every address beyond 16 bits
  }
  const std::string in = tmp("garbage.aedat");
  writeBytes(in, aedat(records));
  const std::string out = tmp("garbage.txt");
  const ToolRun r = run("--input " + in + " --output " + out);
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"events\":0,")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"records\":1000,\"skipped\":{\"sync\":0,\"aps\":0,\"imu\":0,\"out_of_range\":1000}"))
      << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"outside_sensor\":1000,")) << r.out;
  EXPECT_NE(std::string::npos,
            r.out.find("convert: warning: " + in + ": 1000 records, 0 events; skipped: 1000 outside the DVS128 sensor"))
      << r.out;
  std::remove(in.c_str());
  std::remove(out.c_str());
}

TEST(ConvertTool, BagWithDecreasingTimesIsReported)
{
  const std::string in = tmp("decreasing.bag");
  {
    rosbag::Bag bag(in, rosbag::bagmode::Write);
    dvs_driver::EventStream a, b;
    a.width = b.width = a.height = b.height = 128;
    a.events = {{2000000000, 1, 1, true}, {2500000000, 2, 1, true}};
    b.events = {{1000000000, 3, 1, true}};
    bag.write("/dvs/events", ros::Time(10), *dvs_driver::toMessage(a));
    bag.write("/dvs/events", ros::Time(11), *dvs_driver::toMessage(b));
  }
  for (const std::string name : {"dec.txt", "dec.bag"})
  {
    const ToolRun r = run("--input " + in + " --output " + tmp(name));
    EXPECT_EQ(1, r.status) << r.out;
    EXPECT_NE(std::string::npos, r.out.find(in + ": time goes backwards at 1 event (by up to 1.500000 s; the first at "
                                                 "event 2, t = 1.000000 s)"))
        << r.out;
    EXPECT_EQ(std::string::npos, r.out.find("span_s")) << r.out;
  }
  std::remove(in.c_str());
}

TEST(ConvertTool, EventsOutsideAGivenSensorAreRefusedWithTheCount)
{
  const ToolRun r = run("--input " + kData + "/ucsd_alex_walking_again.aedat --output " + tmp("small.txt") +
                        " --width 64 --height 64");
  EXPECT_EQ(1, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("ucsd_alex_walking_again.aedat: ")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find(" events lie outside the 64x64 sensor (the first, event ")) << r.out;
  std::remove(tmp("small.txt").c_str());
}

TEST(ConvertTool, DuplicatedLinesAreCounted)
{
  const std::string in = tmp("dup.txt");
  {
    FILE* f = std::fopen(in.c_str(), "w");
    for (int i = 0; i < 50; ++i)
      for (int k = 0; k < 2; ++k)
        std::fprintf(f, "0.%06d %d 4 1\n", 100 + i, i);
    std::fclose(f);
  }
  const ToolRun r = run("--input " + in + " --output " + tmp("dup_out.txt"));
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"events\":100,")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"duplicates\":50,")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("convert: warning: " + in + ": 50 exact duplicates (50% of 100 events)"))
      << r.out;
  std::remove(in.c_str());
  std::remove(tmp("dup_out.txt").c_str());
}

TEST(ConvertTool, OptionsAreCheckedByName)
{
  const std::string io = "--input " + kData + "/ucsd_alex_walking_again.aedat --output " + tmp("opt.txt");
  struct Case
  {
    std::string args, message;
  } cases[] = {
      {io + " --width abc --height 128", "convert: parameter '--width': 'abc' is not an integer"},
      {io + " --width 100000 --height 128", "--width must be in [0, 65536] px (got 100000)"},
      {io + " --width 128", "give both --width and --height, or neither"},
      {io + " --packet-period 1e9", "--packet-period must be in [1e-06, 3600] s (got 1e+09)"},
      {io + " --packet-period nan", "--packet-period must be in [1e-06, 3600] s (got nan)"},
      {io + " --packet-period", "convert: option --packet-period needs a value"},
      {io + " --topic /a --topic /b", "convert: option --topic given twice"},
      {io + " --bogus", "convert: unknown option `--bogus`"},
      {"--output x.txt", "--input and --output are required"},
  };
  for (const Case& c : cases)
  {
    const ToolRun r = run(c.args);
    EXPECT_EQ(2, r.status) << c.args << "\n" << r.out;
    EXPECT_NE(std::string::npos, r.out.find(c.message)) << c.args << "\n" << r.out;
    EXPECT_NE(std::string::npos, r.out.find("usage: convert")) << r.out;
  }
  std::remove(tmp("opt.txt").c_str());
}

TEST(ConvertTool, AnInputThatCannotFitInMemoryIsRefusedUpFront)
{
  // A sparse AEDAT file as large as the memory available (it would need 3 times that).
  uint64_t avail_kb = 0;
  {
    FILE* f = std::fopen("/proc/meminfo", "r");
    ASSERT_NE(nullptr, f);
    char key[64];
    unsigned long long v;
    while (std::fscanf(f, "%63s %llu kB", key, &v) == 2)
      if (std::string(key) == "MemAvailable:")
        avail_kb = v;
    std::fclose(f);
  }
  ASSERT_GT(avail_kb, 0u);
  const std::string in = tmp("huge.aedat");
  FILE* f = std::fopen(in.c_str(), "w");
  ASSERT_NE(nullptr, f);
  std::fclose(f);
  ASSERT_EQ(0, ::truncate(in.c_str(), static_cast<off_t>(avail_kb * 1024)));
  const ToolRun r = run("--input " + in + " --output " + tmp("huge.txt"));
  EXPECT_EQ(1, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find(in + ": converting it needs up to ")) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("MiB are available")) << r.out;
  std::remove(in.c_str());
}

// Issue 18: the real sample files of ../shared/data/formats convert to events.txt with exactly
// the answers of their README (count, first and last event, span, size).
namespace
{
struct Known
{
  const char* file;
  size_t events;
  dvs_driver::Event first, last;
  uint32_t width, height;
  const char* format;
};

void expectKnownAnswers(const Known& k)
{
  const std::string out = tmp(std::string(k.file) + ".txt");
  const ToolRun r = run("--input " + std::string(DVS_FORMATS_DATA_DIR) + "/" + k.file + " --output " + out);
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find(std::string("\"format\":\"") + k.format)) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"width\":" + std::to_string(k.width) + ",\"height\":" +
                                          std::to_string(k.height)))
      << r.out;
  const auto events = dvs_driver::readEventsText(out);
  ASSERT_EQ(k.events, events.size()) << k.file;
  EXPECT_EQ(k.first, events.front()) << k.file;
  EXPECT_EQ(k.last, events.back()) << k.file;
  std::remove(out.c_str());
}

dvs_driver::Event ev(uint16_t x, uint16_t y, int64_t t_us, bool p) { return dvs_driver::Event{t_us * 1000, x, y, p}; }
}  // namespace

TEST(ConvertToolFormats, RealSamplesToTextGiveTheDocumentedAnswers)
{
  expectKnownAnswers({"prophesee_evt2_gen3_640x480.raw", 539481, ev(237, 121, 1317888, true), ev(210, 142, 1367888, true),
                      640, 480, "Prophesee RAW EVT 2.0"});
  expectKnownAnswers({"prophesee_evt3_gen41_1280x720.raw", 219596, ev(874, 200, 11718656, false),
                      ev(1218, 572, 11727457, true), 1280, 720, "Prophesee RAW EVT 3.0"});
  expectKnownAnswers({"dvxplorer_320x240.aedat4", 111954, ev(154, 204, 1605537493718345, false),
                      ev(88, 237, 1605537494308262, true), 320, 240, "AEDAT 4.0"});
  expectKnownAnswers({"davis346_346x260.aedat4", 117667, ev(218, 15, 1633953690975950, true),
                      ev(137, 56, 1633953691105949, false), 346, 260, "AEDAT 4.0"});
}

TEST(ConvertToolFormats, EveryWritableFormatRoundTripsExactly)
{
  // The EVT 3.0 sample (TIME_LOW steps back inside it, vectorised events) through each writer
  // and back: the same events as converting it directly.
  const std::string in = std::string(DVS_FORMATS_DATA_DIR) + "/prophesee_evt3_gen41_1280x720.raw";
  const std::string direct = tmp("evt3_direct.txt");
  ASSERT_EQ(0, run("--input " + in + " --output " + direct).status);
  const auto expected = dvs_driver::readEventsText(direct);
  ASSERT_EQ(expected.size(), 219596u);
  for (const char* ext : {".aedat4", ".h5", ".raw", ".bag"})
  {
    const std::string mid = tmp(std::string("evt3_mid") + ext), back = tmp("evt3_back.txt");
    ToolRun r = run("--input " + in + " --output " + mid);
    ASSERT_EQ(0, r.status) << ext << ": " << r.out;
    r = run("--input " + mid + " --output " + back);
    ASSERT_EQ(0, r.status) << ext << ": " << r.out;
    EXPECT_NE(std::string::npos, r.out.find("\"events\":219596,\"span_s\":0.008801,\"width\":1280,\"height\":720"))
        << ext << ": " << r.out;
    const auto events = dvs_driver::readEventsText(back);
    ASSERT_EQ(expected.size(), events.size()) << ext;
    for (size_t i = 0; i < events.size(); ++i)
      ASSERT_EQ(expected[i], events[i]) << ext << " event " << i;
    std::remove(mid.c_str());
    std::remove(back.c_str());
  }
  std::remove(direct.c_str());
}

TEST(ConvertToolFormats, TheDriversFileSourceStreamsEveryFormat)
{
  // What the driver's ~file (FileReplay) and replay.launch read: the same events, streamed.
  for (const char* file : {"prophesee_evt3_gen41_1280x720.raw", "prophesee_evt2_gen3_640x480.raw",
                           "dvxplorer_320x240.aedat4", "davis346_346x260.aedat4"})
  {
    const std::string path = std::string(DVS_FORMATS_DATA_DIR) + "/" + file;
    auto source = dvs_driver::openEventSource(path);
    dvs_driver::EventVector streamed, block;
    while (source->read(block, 10000) > 0)
    {
      streamed.insert(streamed.end(), block.begin(), block.end());
      block.clear();
    }
    const dvs_driver::Recording whole = dvs_driver::readRecording(path);
    ASSERT_EQ(whole.contents.stream.events.size(), streamed.size()) << file;
    EXPECT_TRUE(whole.contents.stream.events == streamed) << file;
    EXPECT_EQ(source->info().width, whole.contents.stream.width) << file;
    source->rewind();
    block.clear();
    ASSERT_GT(source->read(block, 1), 0u);
    EXPECT_EQ(block.front(), streamed.front()) << file << ": rewind";
  }
}

TEST(ConvertTool, ImuOfADavisAedat2FileToImuTxt)
{
  // IMU_rotDisk.aedat: 7,384 IMU samples (51,688 IMU6 records); with --zero-time both files
  // shift by the first event's time.
  const std::string out = tmp("disk_events.txt"), imu = tmp("disk_imu.txt");
  const ToolRun r = run("--input " + kData + "/IMU_rotDisk.aedat --output " + out + " --imu " + imu + " --zero-time");
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"imu_samples\":7384}")) << r.out;
  const auto ref = dvs_driver::readAedat(kData + "/IMU_rotDisk.aedat");
  const auto samples = dvs_driver::readImuText(imu);
  ASSERT_EQ(ref.imu.size(), samples.size());
  const int64_t shift = -ref.stream.events.front().t_ns;
  for (size_t i = 0; i < samples.size(); ++i)
  {
    dvs_driver::ImuSample expected = ref.imu[i];
    expected.t_ns += shift;
    expected.temperature_c = NAN;  // imu.txt has no temperature
    ASSERT_EQ(expected, samples[i]) << i;
  }
  EXPECT_EQ(342081000LL - 341678000LL, samples.front().t_ns);  // first IMU 403 us after the first event
  std::remove(out.c_str());
  std::remove(imu.c_str());
}

TEST(ConvertTool, ImuOfAnAedat4FileAndOfAFileWithout)
{
  const std::string out = tmp("davis346.txt"), imu = tmp("davis346_imu.txt");
  const ToolRun r = run("--input " + std::string(DVS_FORMATS_DATA_DIR) + "/davis346_346x260.aedat4 --output " + out +
                        " --imu " + imu);
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"imu_samples\":130}")) << r.out;
  const auto samples = dvs_driver::readImuText(imu);
  ASSERT_EQ(130u, samples.size());
  EXPECT_EQ(1633953690976628000LL, samples.front().t_ns);
  EXPECT_DOUBLE_EQ(-0.0604248046875 * dvs_driver::kStandardGravity, samples.front().accel[0]);
  // A DVS128 recording has none: a warning, and an imu.txt with its header line only.
  const ToolRun none = run("--input " + kData + "/ucsd_alex_walking_again.aedat --output " + out + " --imu " + imu);
  ASSERT_EQ(0, none.status) << none.out;
  EXPECT_NE(std::string::npos, none.out.find("convert: warning: " + kData +
                                             "/ucsd_alex_walking_again.aedat: no IMU samples (AEDAT 2.0 carries none"))
      << none.out;
  EXPECT_TRUE(dvs_driver::readImuText(imu).empty());
  // An imu.txt that cannot be written is an error naming it.
  const ToolRun bad = run("--input " + kData + "/IMU_rotDisk.aedat --output " + out + " --imu /nonexistent/imu.txt");
  EXPECT_EQ(1, bad.status) << bad.out;
  EXPECT_NE(std::string::npos, bad.out.find("/nonexistent/imu.txt")) << bad.out;
  std::remove(out.c_str());
  std::remove(imu.c_str());
}

TEST(ConvertTool, ImuOfABagBesideItsEvents)
{
  // A bag like the simulator's: events on /dvs/events, sensor_msgs/Imu on /dvs/imu.
  EXPECT_EQ("/dvs/imu", dvs_driver::imuTopicFor("/dvs/events"));
  EXPECT_EQ("/cam0/imu", dvs_driver::imuTopicFor("/cam0/events"));
  EXPECT_EQ("", dvs_driver::imuTopicFor("/dvs/packets"));
  const std::string bag = tmp("imu.bag"), out = tmp("imu_bag_events.txt"), imu = tmp("imu_bag.txt");
  dvs_driver::EventStream s;
  s.width = s.height = 128;
  for (int i = 0; i < 100; ++i)
    s.events.push_back(dvs_driver::Event{1000000000LL + i * 100000, static_cast<uint16_t>(i), 5, i % 2 == 0});
  dvs_driver::writeEventsBag(bag, "/dvs/events", s, 1000000);
  dvs_driver::ImuVector written;
  {
    rosbag::Bag b(bag, rosbag::bagmode::Append);
    for (int k = 0; k < 11; ++k)
    {
      dvs_driver::ImuSample m;
      m.t_ns = 1000000000LL + k * 1000000;
      m.accel[1] = -9.81 + 0.001 * k;
      m.gyro[2] = 0.5 * k;
      written.push_back(m);
      const sensor_msgs::Imu msg = dvs_driver::toImuMessage(m, "dvs", 0.01, 0.1);
      b.write("/dvs/imu", msg.header.stamp, msg);
    }
  }
  const ToolRun r = run("--input " + bag + " --output " + out + " --imu " + imu);
  ASSERT_EQ(0, r.status) << r.out;
  EXPECT_NE(std::string::npos, r.out.find("\"imu_samples\":11}")) << r.out;
  EXPECT_EQ(written, dvs_driver::readImuText(imu));
  for (const std::string& f : {bag, out, imu})
    std::remove(f.c_str());
}
