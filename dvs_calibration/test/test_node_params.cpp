// The calibration node's parameter table: defaults valid, ranges named, the session
// configuration it gives, and the README table equal to the code's.
#include <dvs_calibration/calibration_node_params.h>

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace dvs_calibration;

TEST(CalibrationNodeParams, DefaultsGiveTheThesisSession)
{
  CalibrationNodeParams p;
  EXPECT_EQ(calibrationParamTable(p).validate(), "");
  const SessionConfig c = toSessionConfig(p);
  EXPECT_EQ(c.grid.grid.cols, 7);
  EXPECT_EQ(c.grid.grid.rows, 7);
  EXPECT_EQ(c.window_ns, 75000000);
  EXPECT_EQ(c.detector, DetectorKind::Counts);
  EXPECT_DOUBLE_EQ(c.calibrator.spacing_m, 0.03);
}

TEST(CalibrationNodeParams, BadValuesAreNamed)
{
  CalibrationNodeParams p;
  p.window_s = 0;
  p.width = 240;  // height still 0
  p.grid = "7by7";
  p.detector = "edges";
  const std::string err = calibrationParamTable(p).validate();
  EXPECT_NE(err.find("window must be in [0.001, 10] s (got 0)"), std::string::npos) << err;
  EXPECT_NE(err.find("width and height must both be 0"), std::string::npos) << err;
  EXPECT_NE(err.find("grid:"), std::string::npos) << err;
  EXPECT_NE(err.find("detector must be one of 'counts' 'blink'"), std::string::npos) << err;
  EXPECT_THROW(toSessionConfig(p), std::invalid_argument);
}

TEST(CalibrationNodeParams, ReadmeHoldsTheTable)
{
  std::ifstream in(CALIBRATION_README);
  ASSERT_TRUE(in) << CALIBRATION_README;
  std::stringstream ss;
  ss << in.rdbuf();
  CalibrationNodeParams p;
  const std::string table = calibrationParamTable(p).markdownTable();
  EXPECT_NE(ss.str().find(table), std::string::npos) << "README.md's parameter table should be:\n" << table;
}
