// The progress line (progress_meter.h): known formatting, printing only when enabled and at most
// once per interval, a final line only after a shown one; and the real `convert` stays quiet when
// its stderr is not a terminal (no "\r", no progress line) while still printing its JSON line.
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/progress_meter.h>
#include <dvs_driver/recording.h>
#include <rosbag/bag.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

using dvs_driver::formatProgress;
using dvs_driver::ProgressMeter;

namespace
{
std::string readAll(std::FILE* f)
{
  std::fflush(f);
  std::rewind(f);
  std::string s;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0)
    s.append(buf, n);
  return s;
}

std::string slurp(const std::string& path)
{
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

TEST(ProgressMeter, FormatsEventsPercentSizeAndRate)
{
  EXPECT_EQ(formatProgress("convert", 12345678, 42, 100, 2.0),
            "convert: 12,345,678 events, 42.0 % of 100.0 bytes, 6.2 M events/s");
  EXPECT_EQ(formatProgress("convert", 999, 256000000, 512000000, 1.0),
            "convert: 999 events, 50.0 % of 512.0 MB, 999.0 events/s");
  EXPECT_EQ(formatProgress("track_offline", 1000000, 0, 0, 0.5), "track_offline: 1,000,000 events, 2.0 M events/s");
  EXPECT_EQ(formatProgress("x", 0, 0, 0, 0.0), "x: 0 events");
  // bytes beyond the total (a reader's estimate) never show more than 100 %
  EXPECT_EQ(formatProgress("x", 1500, 3000000000ull, 2000000000ull, 1.0), "x: 1,500 events, 100.0 % of 2.0 GB, 1.5 k events/s");
}

TEST(ProgressMeter, DisabledPrintsNothing)
{
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    ProgressMeter m("convert", 1000, false, 0.0, f);
    for (int i = 0; i < 100; ++i)
      m.update(uint64_t(i), uint64_t(i));
    m.finish(100, 1000);
    EXPECT_EQ(m.linesPrinted(), 0u);
  }
  EXPECT_EQ(readAll(f), "");
  std::fclose(f);
}

TEST(ProgressMeter, EnabledRewritesOneLineAndEndsIt)
{
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  ProgressMeter m("convert", 1000, true, 0.0, f);  // interval 0: every update prints
  m.update(10, 100);
  m.update(20, 500);
  m.finish(30, 1000);
  EXPECT_EQ(m.linesPrinted(), 3u);
  const std::string s = readAll(f);
  EXPECT_EQ(s.rfind("\rconvert: 10 events, 10.0 % of 1.0 kB", 0), 0u) << s;
  EXPECT_NE(s.find("\rconvert: 20 events, 50.0 % of 1.0 kB"), std::string::npos) << s;
  EXPECT_NE(s.find("\rconvert: 30 events, 100.0 % of 1.0 kB"), std::string::npos) << s;
  EXPECT_EQ(s.back(), '\n');
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 1) << "one line, rewritten in place";
  std::fclose(f);
}

TEST(ProgressMeter, AtMostOncePerIntervalAndNoFinalLineForShortRuns)
{
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  ProgressMeter m("convert", 1000, true, 3600.0, f);
  for (int i = 0; i < 100000; ++i)
    m.update(uint64_t(i), 10);
  m.finish(100000, 1000);  // nothing was shown: a short run stays silent
  EXPECT_EQ(m.linesPrinted(), 0u);
  EXPECT_EQ(readAll(f), "");
  std::fclose(f);
}

TEST(ProgressMeter, CallbackTakesTheReadersTotal)
{
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  ProgressMeter m("convert", 0, true, 0.0, f);
  dvs_driver::ReadProgress cb = m.callback();
  cb(5, 250, 1000);
  EXPECT_NE(readAll(f).find("convert: 5 events, 25.0 % of 1.0 kB"), std::string::npos);
  std::fclose(f);
}

// While writing, the total counts events.
TEST(ProgressMeter, WriteProgressCountsEvents)
{
  EXPECT_EQ(formatProgress("convert: writing x.aedat4", 500000, 500000, 1000000, 1.0, dvs_driver::ProgressTotal::Events),
            "convert: writing x.aedat4: 500,000 events, 50.0 % of 1,000,000 events, 500.0 k events/s");
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  ProgressMeter m("convert: writing x.txt", 0, true, 0.0, f);
  m.setTotalEvents(400);
  dvs_driver::WriteProgress cb = m.writeCallback();
  cb(100);
  EXPECT_NE(readAll(f).find("convert: writing x.txt: 100 events, 25.0 % of 400 events"), std::string::npos);
  std::fclose(f);
}

namespace
{
dvs_driver::EventVector rampEvents(size_t n)
{
  dvs_driver::EventVector ev;
  for (size_t i = 0; i < n; ++i)
    ev.push_back(dvs_driver::Event{int64_t(1000000 + i * 1000), uint16_t(i % 128), uint16_t((i / 128) % 128), (i & 1) != 0});
  return ev;
}

// Reports growing, at most one per 65,536 events plus the last, ending at the total.
void expectWriteReports(const std::vector<uint64_t>& calls, size_t total)
{
  ASSERT_FALSE(calls.empty());
  EXPECT_LE(calls.size(), total / 65536 + 2);
  EXPECT_GE(calls.size(), total / 65536);
  for (size_t i = 1; i < calls.size(); ++i)
    EXPECT_GE(calls[i], calls[i - 1]);
  EXPECT_EQ(calls.back(), total);
}
}  // namespace

// The writers of events.txt and bags report their progress (convert shows it while writing).
TEST(ProgressMeter, TextAndBagWritersReportEventsWritten)
{
  const dvs_driver::EventVector ev = rampEvents(200000);
  std::vector<uint64_t> calls;
  std::ostringstream text;
  dvs_driver::writeEventsText(text, ev, [&](uint64_t n) { calls.push_back(n); });
  expectWriteReports(calls, ev.size());
  EXPECT_EQ(calls.front(), 65536u);

  calls.clear();
  const std::string path = ::testing::TempDir() + "/progress_" + std::to_string(::getpid()) + ".bag";
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    const size_t packets = dvs_driver::writeEventsBag(bag, "/dvs/events", ev, 128, 128, 1000000, "dvs",
                                                      [&](uint64_t n) { calls.push_back(n); });
    EXPECT_EQ(packets, 200u);  // 1 ms packets of 1,000 events
  }
  expectWriteReports(calls, ev.size());
  std::remove(path.c_str());
}

// readRecording reports its progress between batches: events and bytes growing, the file's size
// as total, and the last report at the end of the file (EVT 3.0 sample: 219,596 events, 618,052 bytes).
TEST(ProgressMeter, ReadRecordingReportsEventsAndBytes)
{
  std::vector<std::array<uint64_t, 3>> calls;
  const auto r = dvs_driver::readRecording(std::string(DVS_FORMATS_DATA_DIR) + "/prophesee_evt3_gen41_1280x720.raw",
                                           "/dvs/events", [&](uint64_t e, uint64_t b, uint64_t t) {
                                             calls.push_back({e, b, t});
                                           });
  ASSERT_EQ(r.contents.stream.events.size(), 219596u);
  ASSERT_GE(calls.size(), 3u);  // batches of 65,536 events
  for (size_t i = 0; i < calls.size(); ++i)
  {
    EXPECT_EQ(calls[i][2], 618052u);
    EXPECT_LE(calls[i][1], calls[i][2]);
    if (i > 0)
    {
      EXPECT_GT(calls[i][0], calls[i - 1][0]);
      EXPECT_GE(calls[i][1], calls[i - 1][1]);
    }
  }
  EXPECT_EQ(calls.back()[0], 219596u);
  EXPECT_EQ(calls.back()[1], 618052u);
  EXPECT_EQ(formatProgress("convert", calls.back()[0], calls.back()[1], calls.back()[2], 0.5),
            "convert: 219,596 events, 100.0 % of 618.1 kB, 439.2 k events/s");
}

// The real tool with stderr to a file (not a terminal): no progress output at all.
TEST(ProgressMeter, ConvertIsQuietWhenStderrIsNotATerminal)
{
  const std::string dir = ::testing::TempDir();
  const std::string out = dir + "/progress_evt3_" + std::to_string(::getpid()) + ".txt";
  const std::string err = out + ".stderr", json = out + ".json";
  const std::string cmd = std::string(CONVERT_TOOL) + " --input " + DVS_FORMATS_DATA_DIR +
                          "/prophesee_evt3_gen41_1280x720.raw --output " + out + " > " + json + " 2> " + err;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const std::string e = slurp(err), j = slurp(json);
  EXPECT_EQ(e.find('\r'), std::string::npos) << e;
  EXPECT_EQ(e.find("events/s"), std::string::npos) << e;
  EXPECT_NE(j.find("\"events\":219596"), std::string::npos) << j;
  std::remove(out.c_str());
  std::remove(err.c_str());
  std::remove(json.c_str());
}
