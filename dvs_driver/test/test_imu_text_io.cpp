// imu.txt (imu_text_io.h): exact round trips, the Event Camera Dataset layout, and clear errors
// naming file and line for malformed input.
#include <dvs_driver/checked_write.h>
#include <dvs_driver/imu_text_io.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <unistd.h>

using dvs_driver::EventFileError;
using dvs_driver::ImuSample;
using dvs_driver::ImuVector;

namespace
{
std::string errorOf(const std::string& text)
{
  std::istringstream in(text);
  try
  {
    dvs_driver::readImuText(in, "imu.txt");
  }
  catch (const EventFileError& e)
  {
    return e.what();
  }
  return "";
}

ImuVector randomSamples(size_t n)
{
  std::mt19937_64 rng(42);
  std::normal_distribution<double> g(0.0, 5.0);
  ImuVector v;
  int64_t t = -1500000000;  // negative times are written and read too
  for (size_t i = 0; i < n; ++i)
  {
    ImuSample s;
    t += 1 + static_cast<int64_t>(rng() % 2000000);
    s.t_ns = t;
    for (int a = 0; a < 3; ++a)
    {
      s.accel[a] = g(rng);
      s.gyro[a] = g(rng) * 1e-3;
    }
    v.push_back(s);
  }
  v[3].accel[0] = 1e-300;  // extremes of the decimal form
  v[4].gyro[2] = -1.7976931348623157e308;
  v[5].accel[1] = 0.0;
  return v;
}
}  // namespace

TEST(ImuTextIo, ReadsTheEventCameraDatasetLayout)
{
  // Two lines of the Event Camera Dataset's shapes_rotation/imu.txt layout, a comment, a blank.
  std::istringstream in("# t ax ay az gx gy gz\n"
                        "1468940145.227514000 0.397000 9.790000 -0.187000 0.047000 -0.012000 0.003000\n"
                        "\n"
                        "1468940145.228514 +1e-2 -9.81 0 -0.5 0.25 1E3\r\n");
  const ImuVector v = dvs_driver::readImuText(in, "imu.txt");
  ASSERT_EQ(2u, v.size());
  EXPECT_EQ(1468940145227514000LL, v[0].t_ns);
  EXPECT_DOUBLE_EQ(0.397, v[0].accel[0]);
  EXPECT_DOUBLE_EQ(9.79, v[0].accel[1]);
  EXPECT_DOUBLE_EQ(-0.187, v[0].accel[2]);
  EXPECT_DOUBLE_EQ(0.047, v[0].gyro[0]);
  EXPECT_DOUBLE_EQ(-0.012, v[0].gyro[1]);
  EXPECT_DOUBLE_EQ(0.003, v[0].gyro[2]);
  EXPECT_TRUE(std::isnan(v[0].temperature_c));
  EXPECT_EQ(1468940145228514000LL, v[1].t_ns);
  EXPECT_DOUBLE_EQ(0.01, v[1].accel[0]);
  EXPECT_DOUBLE_EQ(1000.0, v[1].gyro[2]);
}

TEST(ImuTextIo, RoundTripIsExact)
{
  const ImuVector in = randomSamples(2000);
  std::stringstream s;
  dvs_driver::writeImuText(s, in);
  EXPECT_EQ(0u, s.str().rfind(dvs_driver::kImuTextHeader, 0));
  const ImuVector out = dvs_driver::readImuText(s, "memory");
  ASSERT_EQ(in.size(), out.size());
  for (size_t i = 0; i < in.size(); ++i)
    ASSERT_EQ(in[i], out[i]) << i << ": " << dvs_driver::formatImuLine(in[i]);
}

TEST(ImuTextIo, FileRoundTripAndLineFormat)
{
  ImuSample s;
  s.t_ns = 2000000001;
  s.accel[1] = 9.81;
  s.gyro[2] = -0.5;
  EXPECT_EQ("2.000000001 0 9.81 0 0 0 -0.5", dvs_driver::formatImuLine(s));
  s.t_ns = -1;
  EXPECT_EQ("-0.000000001 0 9.81 0 0 0 -0.5", dvs_driver::formatImuLine(s));
  const std::string path = "/tmp/test_imu_text_io_" + std::to_string(::getpid()) + ".txt";
  const ImuVector in = randomSamples(50);
  dvs_driver::writeImuText(path, in);
  EXPECT_EQ(in, dvs_driver::readImuText(path));
  std::remove(path.c_str());
}

TEST(ImuTextIo, MalformedLinesAreNamedWithFileAndLine)
{
  const std::string ok = "1.0 0 0 9.81 0 0 0\n";
  EXPECT_NE(std::string::npos, errorOf(ok + "2.0 0 0 9.81 0 0\n").find("imu.txt:2: expected 7 fields"));
  EXPECT_NE(std::string::npos, errorOf(ok + "2.0 0 0 9.81 0 0 0 7\n").find("imu.txt:2: more than 7 fields"));
  EXPECT_NE(std::string::npos, errorOf("abc 0 0 9.81 0 0 0\n").find("imu.txt:1: time `abc`"));
  EXPECT_NE(std::string::npos, errorOf(ok + ok + "3.0 0 x 9.81 0 0 0\n").find("imu.txt:3: ay `x` is not a number"));
  EXPECT_NE(std::string::npos, errorOf("1.0 0 0 9.81 0 0 0.1.2\n").find("imu.txt:1: gz `0.1.2` is not a number"));
  EXPECT_NE(std::string::npos, errorOf("1.0 nan 0 9.81 0 0 0\n").find("imu.txt:1: ax `nan` is not finite"));
  EXPECT_NE(std::string::npos, errorOf("1.0 0 0 9.81 inf 0 0\n").find("imu.txt:1: gx `inf` is not finite"));
  EXPECT_NE(std::string::npos, errorOf("1.0 0 0 1e999 0 0 0\n").find("imu.txt:1: az `1e999` is out of range"));
  EXPECT_NE(std::string::npos, errorOf(ok + "0.5 0 0 9.81 0 0 0\n").find("imu.txt:2: time goes backwards"));
  EXPECT_EQ("", errorOf(ok + ok));  // equal times are kept
  try
  {
    dvs_driver::readImuText("/nonexistent/imu.txt");
    FAIL();
  }
  catch (const EventFileError& e)
  {
    EXPECT_NE(std::string::npos, std::string(e.what()).find("/nonexistent/imu.txt: cannot open IMU file"));
  }
}

TEST(ImuTextIo, WriterRefusesNonFiniteValuesAndLeavesNoFile)
{
  ImuVector v(3);
  v[2].gyro[1] = NAN;
  const std::string path = "/tmp/test_imu_text_io_nan_" + std::to_string(::getpid()) + ".txt";
  try
  {
    dvs_driver::writeImuText(path, v);
    FAIL();
  }
  catch (const EventFileError& e)
  {
    EXPECT_NE(std::string::npos, std::string(e.what()).find("IMU sample 2 has a non-finite value"));
  }
  EXPECT_NE(0, ::access(path.c_str(), F_OK));
  EXPECT_THROW(dvs_driver::writeImuText("/nonexistent/dir/imu.txt", ImuVector(1)), dvs_driver::WriteError);
}
