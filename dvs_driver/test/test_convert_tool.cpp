// Runs the real `convert` executable on the real recordings and checks its JSON line and outputs.
#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_text_io.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
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
