// The package README's parameter tables are what the parameter tables print (one list of names,
// units, bounds and documentation per ROS class; the YAML configuration's run parameters too).
#include <dvs_screen_sim/screen_loop/screen_loop_params.h>
#include <dvs_screen_sim/simulator_params.h>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace dvs_screen_sim;

namespace
{
std::string readme()
{
  std::ifstream in(DVS_SCREEN_SIM_README);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void expectInReadme(const dvs_driver::ParamTable& table)
{
  const std::string text = readme();
  ASSERT_FALSE(text.empty()) << DVS_SCREEN_SIM_README;
  for (const auto& e : table.entries())
    EXPECT_NE(text.find("| `" + e.name + "` |"), std::string::npos) << table.what() << ": " << e.name << " not in the README";
  EXPECT_NE(text.find(table.markdownTable()), std::string::npos)
      << table.what() << ": the README's table differs from the table's; it should read:\n"
      << table.markdownTable();
}
}  // namespace

TEST(ParamTables, SimulatorNodeTableIsInTheReadme)
{
  SimulatorParams p;
  expectInReadme(simulatorParamTable(p));
}

TEST(ParamTables, ScreenLoopNodeTableIsInTheReadme)
{
  screen_loop::ScreenLoopParams p;
  expectInReadme(screen_loop::screenLoopParamTable(p));
}

TEST(ParamTables, ConfigurationRunParametersAreInTheReadme)
{
  SimRunParams p;
  expectInReadme(simRunParamTable(p));
}

TEST(ParamTables, ConfigurationImuParametersAreInTheReadme)
{
  ImuSimParams p;
  expectInReadme(imuParamTable(p));
}

TEST(ParamTables, DefaultsAreValidAndBadValuesAreNamed)
{
  SimulatorParams p;
  dvs_driver::ParamTable t = simulatorParamTable(p);
  EXPECT_EQ(t.validate(), "");
  p.run.packet_period = 0;
  EXPECT_NE(t.validate().find("packet_period"), std::string::npos);
  EXPECT_NE(t.setFromText("packet_period_ms", "1").find("packet_period_ms"), std::string::npos);  // unknown name
  screen_loop::ScreenLoopParams s;
  dvs_driver::ParamTable st = screen_loop::screenLoopParamTable(s);
  EXPECT_EQ(st.validate(), "");
  s.fullscreen = false;
  s.width = 10;
  EXPECT_NE(st.validate().find("width"), std::string::npos);
  s.width = 640;
  s.detector = "hough";
  EXPECT_NE(st.validate().find("detector"), std::string::npos);
}
