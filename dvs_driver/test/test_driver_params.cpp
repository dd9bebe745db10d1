// The driver's parameter table: defaults valid, bounds refuse out-of-range values with a message
// naming the parameter, and the README's parameter table is the table this code prints.
#include <dvs_driver/driver_params.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace
{
std::string readFile(const std::string& path)
{
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST(DriverParams, DefaultsAreValid)
{
  dvs_driver::DriverParams p;
  const dvs_driver::ParamTable t = dvs_driver::driverParamTable(p);
  EXPECT_EQ("", t.validate());
  EXPECT_EQ(1000000, p.packetPeriodNs());
  EXPECT_EQ(1000u, p.publisherQueueSize());  // a camera
  p.file = "x.aedat";
  EXPECT_EQ(0u, p.publisherQueueSize());  // a recording played once
}

TEST(DriverParams, OutOfRangeValuesAreRefusedNamingTheParameter)
{
  struct Case
  {
    const char* name;
    const char* value;
    const char* expected;
  } cases[] = {
      {"packet_period", "5", "packet_period must be in [1e-05, 1] s (got 5)"},
      {"packet_period", "0", "packet_period must be in [1e-05, 1] s (got 0)"},
      {"max_events", "0", "max_events must be in [1, 1e+07] events (got 0)"},
      {"replay_speed", "-1", "replay_speed must be >= 0 x real time (got -1)"},
      {"transfers", "65", "transfers must be in [1, 64] (got 65)"},
      {"transfer_size", "1000", "transfer_size must be a multiple of 512 bytes (got 1000)"},
      {"reconnect_interval", "0", "reconnect_interval must be > 0 s (got 0)"},
      {"queue_size", "-2", "queue_size must be in [-1, 1e+08] packets (got -2)"},
      {"file_time", "now", "file_time must be one of 'replay' 'original' (got 'now')"},
      {"bias_preset", "fastest", "bias_preset must be one of 'fast' 'standard' 'slow' (got 'fastest')"},
      {"frame_id", "", "frame_id must not be empty"},
  };
  for (const Case& c : cases)
  {
    SCOPED_TRACE(c.name);
    dvs_driver::DriverParams p;
    dvs_driver::ParamTable t = dvs_driver::driverParamTable(p);
    ASSERT_EQ("", t.setFromText(c.name, c.value));
    EXPECT_NE(std::string::npos, t.validate().find(c.expected)) << t.validate();
    try
    {
      t.validateOrThrow();
      ADD_FAILURE() << "accepted " << c.name << " = " << c.value;
    }
    catch (const std::invalid_argument& e)
    {
      EXPECT_NE(std::string::npos, std::string(e.what()).find("dvs_driver")) << e.what();
      EXPECT_NE(std::string::npos, std::string(e.what()).find(c.expected)) << e.what();
    }
  }
}

TEST(DriverParams, ReadmeTableIsThePrintedTable)
{
  dvs_driver::DriverParams p;
  const dvs_driver::ParamTable t = dvs_driver::driverParamTable(p);
  const std::string readme = readFile(DVS_DRIVER_README);
  ASSERT_FALSE(readme.empty()) << DVS_DRIVER_README;
  const std::string table = t.markdownTable();
  EXPECT_NE(std::string::npos, readme.find(table))
      << "dvs_driver/README.md's parameter table differs from the code's; paste this table there:\n"
      << table;
  for (const auto& e : t.entries())
    EXPECT_NE(std::string::npos, readme.find("`" + e.name + "`")) << e.name;
  for (const auto& name : dvs_driver::driverAlsoKnownParams())
    EXPECT_NE(std::string::npos, readme.find(name)) << name;
}
