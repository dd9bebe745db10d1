// The progress line (progress_meter.h): known formatting, printing only when enabled and at most
// once per interval, a final line only after a shown one; and the real `convert` stays quiet when
// its stderr is not a terminal (no "\r", no progress line) while still printing its JSON line.
#include <dvs_driver/progress_meter.h>

#include <gtest/gtest.h>

#include <algorithm>
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
