// The offline tools with hostile input and faults (issue 19): every failure is an exit code
// with a message naming the problem, never a crash, an abort or silence. A full disk is a link
// to /dev/full (root can write anywhere, so read-only folders prove nothing).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace fs = std::filesystem;

namespace
{
struct Result
{
  int exit_code = -1;  ///< -1: killed by a signal (a crash or an abort)
  std::string err;
};

Result run(const std::string& command)
{
  const std::string log = (fs::temp_directory_path() / ("tool_err_" + std::to_string(::getpid()))).string();
  const int status = std::system((command + " > /dev/null 2> " + log).c_str());
  std::ifstream in(log);
  Result r;
  r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  fs::remove(log);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// A small simulated dataset (events.txt, calib.txt, map.yaml), made once per test binary.
const std::string& dataset()
{
  static const std::string dir = [] {
    const std::string d = (fs::temp_directory_path() / ("tool_err_data_" + std::to_string(::getpid()))).string();
    const Result r = run(std::string(SIMULATE_TOOL) + " --scenario flip --duration 0.3 --out " + d);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return d;
  }();
  return dir;
}

std::string fullDiskLink(const std::string& name)
{
  const std::string link = (fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()))).string();
  fs::remove(link);
  fs::create_symlink("/dev/full", link);
  return link;
}

std::string track(const std::string& extra)
{
  const std::string& d = dataset();
  return std::string(TRACK_OFFLINE_TOOL) + " --events " + d + "/events.txt --calib " + d + "/calib.txt --map " + d +
         "/map.yaml " + extra;
}
}  // namespace

TEST(ToolErrors, TrackOfflineOutputOnAFullDiskOrMissingFolder)
{
  const std::string full = fullDiskLink("full_traj.txt");
  Result r = run(track("--out " + full));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("full_traj.txt"), std::string::npos) << r.err;
  fs::remove(full);

  r = run(track("--out /nonexistent_folder_xyz/traj.txt"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/nonexistent_folder_xyz"), std::string::npos) << r.err;
}

TEST(ToolErrors, TrackOfflineNamesBadOptions)
{
  Result r = run(track("--out /dev/null --width abc --height 128"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("--width must be a whole number in [1, 4096] (got 'abc')"), std::string::npos) << r.err;
  r = run(track("--out /dev/null --width 60000 --height 60000"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("--width must be a whole number in [1, 4096]"), std::string::npos) << r.err;
}

TEST(ToolErrors, TrackOfflineRefusesEventsOutsideAnAssumedSize)
{
  // A 240x180 recording given without its size: refused, naming the file, the event and the size.
  const std::string dir = (fs::temp_directory_path() / ("tool_err_240_" + std::to_string(::getpid()))).string();
  fs::create_directories(dir);
  std::ofstream(dir + "/events.txt") << "0.001000000 10 10 1\n0.002000000 200 150 0\n";
  std::ofstream(dir + "/calib.txt") << "200 200 119.5 89.5 0 0 0 0 0\n";
  Result r = run(std::string(TRACK_OFFLINE_TOOL) + " --events " + dir + "/events.txt --calib " + dir +
                 "/calib.txt --out /dev/null");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("events.txt: event 2 (t 0.002000000 s, x 200, y 150) lies outside the assumed 128x128 sensor"),
            std::string::npos)
      << r.err;
  // With its size it is accepted.
  r = run(std::string(TRACK_OFFLINE_TOOL) + " --events " + dir + "/events.txt --calib " + dir +
          "/calib.txt --width 240 --height 180 --out /dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  fs::remove_all(dir);
}

TEST(ToolErrors, SimulateBagOnAFullDiskIsANamedErrorNotAnAbort)
{
  const std::string dir = (fs::temp_directory_path() / ("tool_err_sim_" + std::to_string(::getpid()))).string();
  fs::create_directories(dir);
  fs::create_symlink("/dev/full", dir + "/events.bag");
  Result r = run(std::string(SIMULATE_TOOL) + " --scenario flip --duration 0.05 --bag --out " + dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;  // an uncaught rosbag exception used to abort (-1 here)
  EXPECT_NE(r.err.find("events.bag"), std::string::npos) << r.err;
  fs::remove_all(dir);

  fs::create_directories(dir);
  fs::create_symlink("/dev/full", dir + "/events.txt");
  r = run(std::string(SIMULATE_TOOL) + " --scenario flip --duration 0.05 --out " + dir);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

TEST(ToolErrors, CalibrateDebugImagesIntoAMissingFolder)
{
  const std::string& d = dataset();
  const Result r = run(std::string(CALIBRATE_TOOL) + " --events " + d + "/events.txt --spacing 0.03 --out /dev/null" +
                       " --debug-images /nonexistent_folder_xyz");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/nonexistent_folder_xyz/window_"), std::string::npos) << r.err;
}

TEST(ToolErrors, TrackOfflineSaysWhatIsWrongWithItsInput)
{
  // Every line of an events file twice: tracked as given, but said (it used to never initialise
  // without a word), and counted in the JSON summary.
  const std::string& d = dataset();
  const std::string dup = (fs::temp_directory_path() / ("tool_err_dup_" + std::to_string(::getpid()))).string();
  {
    std::ifstream in(d + "/events.txt");
    std::ofstream out(dup);
    std::string line;
    while (std::getline(in, line))
      out << line << "\n" << (line.empty() || line[0] == '#' ? "" : line + "\n");
  }
  const std::string json = (fs::temp_directory_path() / ("tool_err_json_" + std::to_string(::getpid()))).string();
  const int status = std::system((std::string(TRACK_OFFLINE_TOOL) + " --events " + dup + " --calib " + d +
                                  "/calib.txt --out /dev/null > " + json + " 2> " + json + ".err")
                                     .c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  std::ifstream jin(json), ein(json + ".err");
  const std::string out((std::istreambuf_iterator<char>(jin)), std::istreambuf_iterator<char>());
  const std::string err((std::istreambuf_iterator<char>(ein)), std::istreambuf_iterator<char>());
  EXPECT_NE(err.find("exact duplicates (50%"), std::string::npos) << err;
  EXPECT_NE(out.find("\"duplicates\":"), std::string::npos) << out;
  EXPECT_EQ(out.find("\"duplicates\":0"), std::string::npos) << out;
  fs::remove(dup);
  fs::remove(json);
  fs::remove(json + ".err");

  // Not a recording at all: a named error.
  const std::string garbage = (fs::temp_directory_path() / ("tool_err_garbage_" + std::to_string(::getpid()))).string();
  std::ofstream(garbage) << "#!AER-DAT2.0\r\n" << std::string(1001, '\x7f');
  const Result r = run(std::string(TRACK_OFFLINE_TOOL) + " --aedat " + garbage + " --preset dvs128 --out /dev/null");
  EXPECT_NE(r.exit_code, -1) << r.err;
  EXPECT_NE(r.err.find(garbage), std::string::npos) << r.err;
  fs::remove(garbage);
}

TEST(ToolErrors, TrackOfflineImuOptionsSayWhatIsWrong)
{
  const std::string& d = dataset();
  // The simulator's imu.txt is fused: the JSON says so.
  const std::string json = (fs::temp_directory_path() / ("tool_err_imu_" + std::to_string(::getpid()))).string();
  const int status = std::system((track("--out /dev/null --imu " + d + "/imu.txt") + " > " + json + " 2> /dev/null").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  std::ifstream jin(json);
  const std::string out((std::istreambuf_iterator<char>(jin)), std::istreambuf_iterator<char>());
  EXPECT_NE(out.find("\"imu\": {\"status\""), std::string::npos) << out;
  fs::remove(json);
  // A missing imu.txt: named.
  Result r = run(track("--out /dev/null --imu /nonexistent/imu.txt"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/imu.txt"), std::string::npos) << r.err;
  // A malformed one: named with its line.
  const std::string bad = (fs::temp_directory_path() / ("tool_err_badimu_" + std::to_string(::getpid()))).string();
  std::ofstream(bad) << "0.0 0 9.81 0 0 0\n";
  r = run(track("--out /dev/null --imu " + bad));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(bad), std::string::npos) << r.err;
  fs::remove(bad);
  // events.txt carries no IMU: `--imu recording` says so.
  r = run(track("--out /dev/null --imu recording"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("carries no IMU samples"), std::string::npos) << r.err;
  // --odometry without --imu.
  r = run(track("--out /dev/null --odometry /dev/null"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("--odometry needs --imu"), std::string::npos) << r.err;
  // A bad IMU vector parameter: named.
  const std::string params = (fs::temp_directory_path() / ("tool_err_imuparams_" + std::to_string(::getpid()))).string();
  std::ofstream(params) << "imu_q_camera_imu: \"0 0 1\"\n";
  r = run(track("--out /dev/null --imu " + d + "/imu.txt --params " + params));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("imu_q_camera_imu"), std::string::npos) << r.err;
  fs::remove(params);
}

TEST(ToolErrors, PythonToolsGiveOneLineErrorsNotTracebacks)
{
  // dvs_launch's scripts (the demo report, the metric's plot, bag conversion) on missing inputs.
  const std::string py = std::string("/usr/bin/python3 ") + LAUNCH_SCRIPTS_DIR;
  for (const std::string& cmd : {py + "/bag_to_tum.py /nonexistent/run.bag /pose /tmp/out.tum",
                                 py + "/evaluate_trajectory.py --gt /nonexistent/gt.txt --est /nonexistent/est.txt",
                                 py + "/demo_report.py /nonexistent_demo_dir"})
  {
    const Result r = run(cmd);
    EXPECT_EQ(r.exit_code, 1) << cmd << "\n" << r.err;
    EXPECT_EQ(r.err.find("Traceback"), std::string::npos) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find("/nonexistent"), std::string::npos) << cmd << "\n" << r.err;
  }
}
