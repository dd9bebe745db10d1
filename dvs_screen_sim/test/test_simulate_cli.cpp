// The `simulate` command line (other packages' tests depend on exactly this interface).
#include <dvs_driver/imu_text_io.h>
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace
{
int run(const std::string& args)
{
  const std::string cmd = std::string(SIMULATE_EXECUTABLE) + " " + args + " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Exit code, and stderr into `err`.
int runCapture(const std::string& args, std::string& err)
{
  const std::string log = std::filesystem::temp_directory_path() / ("dvs_sim_cli_err_" + std::to_string(::getpid()));
  const std::string cmd = std::string(SIMULATE_EXECUTABLE) + " " + args + " > /dev/null 2> " + log;
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  std::filesystem::remove(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string tempDir(const std::string& name)
{
  const auto dir = std::filesystem::temp_directory_path() / ("dvs_screen_sim_cli_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir.string();
}
}  // namespace

TEST(SimulateCli, WritesTheDatasetFolderAndTheBag)
{
  const std::string dir = tempDir("ok");
  ASSERT_EQ(run("--scenario helix --out " + dir + " --seed 3 --duration 0.05 --bag"), 0);
  for (const char* f : {"events.txt", "groundtruth.txt", "calib.txt", "map.yaml", "config.yaml", "events.bag"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  std::ifstream gt(dir + "/groundtruth.txt");
  std::string line;
  int lines = 0;
  while (std::getline(gt, line))
    lines += !line.empty() && line[0] != '#';
  EXPECT_EQ(lines, 51);  // 1 kHz over 0.05 s
  // imu.txt and the true biases beside events.txt, readable by the suite's imu.txt reader.
  const dvs_driver::ImuVector imu = dvs_driver::readImuText(dir + "/imu.txt");
  const dvs_driver::ImuVector bias = dvs_driver::readImuText(dir + "/imu_bias_groundtruth.txt");
  ASSERT_EQ(imu.size(), 51u);  // 1 kHz over 0.05 s
  ASSERT_EQ(bias.size(), 51u);
  EXPECT_EQ(imu[50].t_ns, 50000000);
  for (size_t k = 0; k < imu.size(); ++k)
  {
    EXPECT_EQ(bias[k].t_ns, imu[k].t_ns);
    // The helix circles at ~0.5 m radius and pi rad/s (~5 m/s^2 centripetal, plus the distance's
    // growth), so |specific force| lies within 9.81 +- 5.5 (no impulse at the start, where it sets off).
    const double f = std::sqrt(imu[k].accel[0] * imu[k].accel[0] + imu[k].accel[1] * imu[k].accel[1] +
                               imu[k].accel[2] * imu[k].accel[2]);
    EXPECT_NEAR(f, 9.81, 5.5) << k;
    EXPECT_LE(std::sqrt(bias[k].accel[0] * bias[k].accel[0] + bias[k].accel[1] * bias[k].accel[1] +
                        bias[k].accel[2] * bias[k].accel[2]),
              0.06);
  }
  std::filesystem::remove_all(dir);
}

TEST(SimulateCli, RejectsBadArgumentsAndConfigurations)
{
  const std::string dir = tempDir("bad");
  EXPECT_EQ(run("--scenario flip"), 2);                                   // no --out
  EXPECT_EQ(run("--scenario flip --out " + dir + " --seed -4"), 2);       // bad seed
  EXPECT_EQ(run("--scenario flip --out " + dir + " --duration zero"), 2);
  EXPECT_EQ(run("--scenario flip --out " + dir + " --frobnicate"), 2);
  EXPECT_EQ(run("--scenario spiral --out " + dir), 1);                    // unknown scenario
  EXPECT_EQ(run("--scenario flip --out " + dir + " --config /nonexistent.yaml"), 1);
  const std::string cfg = dir + ".yaml";
  std::ofstream(cfg) << "events: {threshold_on: -0.2}\n";
  EXPECT_EQ(run("--scenario flip --out " + dir + " --config " + cfg), 1);
  std::filesystem::remove(cfg);
  std::filesystem::remove_all(dir);
}

TEST(SimulateCli, RefusesRunsTooLongUpFrontWithTheEstimate)
{
  // Used to run until killed; now refused before anything is simulated or written.
  const std::string dir = tempDir("long");
  std::string err;
  EXPECT_EQ(runCapture("--scenario flip --out " + dir + " --duration 1e7", err), 1);
  EXPECT_NE(err.find("more than the simulator runs at once"), std::string::npos) << err;
  EXPECT_NE(err.find("MB at 1000"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/events.txt"));
  std::filesystem::remove_all(dir);
}
