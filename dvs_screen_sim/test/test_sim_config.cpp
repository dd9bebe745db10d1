#include <dvs_driver/event_text_io.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/sim_config.h>
#include <dvs_calibration/trajectory_file.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace dvs_screen_sim;

namespace
{
std::string slurp(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string tempDir(const std::string& name)
{
  const auto dir = std::filesystem::temp_directory_path() / ("dvs_screen_sim_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir.string();
}

std::string emit(const YAML::Node& n)
{
  YAML::Emitter e;
  e << n;
  return e.c_str();
}
}  // namespace

TEST(SimConfig, DefaultsResolveForEveryScenario)
{
  for (const auto& s : scenarioNames())
  {
    if (s == "file")
    {
      EXPECT_THROW(resolveSimConfig(s, YAML::Node()), ConfigError);  // needs a path
      continue;
    }
    const SimConfig c = resolveSimConfig(s, YAML::Node());
    EXPECT_GT(c.duration, 0) << s;
    EXPECT_EQ(c.camera.width(), 128);
    EXPECT_EQ(c.scene.polygons.size(), 1u);
    EXPECT_TRUE(makeTrajectory(c) != nullptr);
  }
  EXPECT_DOUBLE_EQ(resolveSimConfig("flip", YAML::Node()).duration, 1.5);
  EXPECT_DOUBLE_EQ(resolveSimConfig("helix", YAML::Node()).duration, 4.0);
}

TEST(SimConfig, OverridesPresetsAndErrorsNameTheParameter)
{
  const SimConfig c = resolveSimConfig(
      "circle",
      YAML::Load("{camera: {preset: davis346, fx: 300}, events: {threshold_on: 0.25, noise: {preset: noisy, "
                 "background_rate: 0.5}}, trajectory: {circle: {distance: 1.7}}}"),
      11, 0.5);
  EXPECT_EQ(c.camera.width(), 346);
  EXPECT_DOUBLE_EQ(c.camera.intrinsics().fx, 300);
  EXPECT_DOUBLE_EQ(c.events.threshold_on, 0.25);
  EXPECT_DOUBLE_EQ(c.events.noise.background_rate, 0.5);
  EXPECT_DOUBLE_EQ(c.events.noise.threshold_sigma, noisePreset("noisy").threshold_sigma);
  EXPECT_EQ(c.seed, 11u);
  EXPECT_DOUBLE_EQ(c.duration, 0.5);
  EXPECT_NEAR(makeTrajectory(c)->poseAt(0.1).p_world_camera().norm(), 1.7, 1e-9);
  // The resolved tree holds the preset's values.
  EXPECT_DOUBLE_EQ(c.resolved["events"]["noise"]["latency"].as<double>(), noisePreset("noisy").latency);
  EXPECT_EQ(c.resolved["camera"]["height"].as<int>(), 260);

  auto message = [](const char* yaml) {
    try
    {
      resolveSimConfig("flip", YAML::Load(yaml));
    }
    catch (const ConfigError& e)
    {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("{trajectory: {flip: {peak_rate: 3}}}").find("trajectory.flip.peak_rate"), std::string::npos);
  EXPECT_NE(message("{events: {threshold_on: -1}}").find("threshold_on"), std::string::npos);
  EXPECT_NE(message("{events: {noise: {preset: loud}}}").find("loud"), std::string::npos);
  EXPECT_NE(message("{camera: {preset: dvs999}}").find("camera"), std::string::npos);
  EXPECT_NE(message("{sampling: {max_pixel_motion: zero}}").find("sampling.max_pixel_motion"), std::string::npos);
  EXPECT_NE(message("{trajectory: {flip: {distance: -2}}}").find("distance"), std::string::npos);
  EXPECT_THROW(resolveSimConfig("spiral", YAML::Node()), ConfigError);
}

TEST(SimConfig, CameraFromACalibrationFile)
{
  const std::string dir = tempDir("cam");
  std::filesystem::create_directories(dir);
  dvs_calibration::saveCameraInfoYaml(dir + "/cam.yaml", dvs_calibration::CameraModel::davis240(), "test");
  YAML::Node over;
  over["camera"]["calibration_file"] = dir + "/cam.yaml";
  over["camera"]["k1"] = 0.0;
  const SimConfig c = resolveSimConfig("flip", over);
  EXPECT_EQ(c.camera.width(), 240);
  EXPECT_EQ(c.camera.height(), 180);
  EXPECT_DOUBLE_EQ(c.camera.intrinsics().fx, dvs_calibration::CameraModel::davis240().intrinsics().fx);
  EXPECT_DOUBLE_EQ(c.camera.intrinsics().k1, 0.0);  // individual override on top of the file
  over["camera"]["calibration_file"] = dir + "/missing.yaml";
  EXPECT_THROW(resolveSimConfig("flip", over), ConfigError);
  std::filesystem::remove_all(dir);
}

TEST(SimConfig, ResolvedConfigReproducesItself)
{
  const SimConfig a = resolveSimConfig("random", YAML::Load("{events: {noise: {preset: realistic}}}"), 4, 0.2);
  const SimConfig b = resolveSimConfig("random", a.resolved);
  EXPECT_EQ(emit(a.resolved), emit(b.resolved));
}

TEST(Dataset, FilesAreCompleteConsistentAndReproducible)
{
  const SimConfig c = resolveSimConfig("flip", YAML::Load("{trajectory: {flip: {first_flip_time: 0.1}}}"), 2, 0.2);
  const std::string d1 = tempDir("a"), d2 = tempDir("b");
  writeDataset(d1, c, runSimulation(c));
  writeDataset(d2, c, runSimulation(c));
  for (const char* f : {"events.txt", "groundtruth.txt", "calib.txt", "map.yaml", "config.yaml", "camera_info.yaml"})
  {
    ASSERT_TRUE(std::filesystem::exists(d1 + "/" + f)) << f;
    EXPECT_EQ(slurp(d1 + "/" + f), slurp(d2 + "/" + f)) << f << " differs between identical runs";
  }
  const auto events = dvs_driver::readEventsText(d1 + "/events.txt");
  ASSERT_GT(events.size(), 1000u);
  const dvs_calibration::Trajectory gt = dvs_calibration::readTumTrajectory(d1 + "/groundtruth.txt");
  ASSERT_EQ(gt.size(), 201u);  // 1 kHz over 0.2 s
  EXPECT_DOUBLE_EQ(gt.front().t, 0.0);
  EXPECT_GE(events.front().t_ns, 0);
  EXPECT_LE(events.back().t_ns, 200000000 + 1000000);  // same time base (+ realistic latency)
  const auto cam = dvs_calibration::loadCalibTxt(d1 + "/calib.txt", 128, 128);
  EXPECT_DOUBLE_EQ(cam.intrinsics().fx, c.camera.intrinsics().fx);
  const YAML::Node map = YAML::LoadFile(d1 + "/map.yaml");
  EXPECT_EQ(map["frame_id"].as<std::string>(), "world");
  EXPECT_EQ(map["segments"].size(), 4u);
  EXPECT_DOUBLE_EQ(map["up"][1].as<double>(), 1.0);
  // Re-running from the written config.yaml gives the same events.
  const SimConfig again = resolveSimConfigFile("flip", d1 + "/config.yaml");
  EXPECT_EQ(runSimulation(again).events, events);
  std::filesystem::remove_all(d1);
  std::filesystem::remove_all(d2);
}

TEST(Dataset, StreamedChunksEqualTheInMemoryRun)
{
  YAML::Node over = YAML::Load("{events: {noise: {preset: noisy}}, trajectory: {flip: {first_flip_time: 0.1}}}");
  over["time_offset"] = 0.0123456;  // chunk boundaries must follow absolute time
  const SimConfig c = resolveSimConfig("flip", over, 8, 0.35);
  const SimulationOutput whole = runSimulation(c);
  dvs_driver::EventVector streamed;
  int chunks = 0;
  const SimulationOutput parts = runSimulation(c, [&](const dvs_driver::EventVector& chunk) {
    ASSERT_FALSE(chunk.empty());
    if (!streamed.empty())  // no packet period (1 ms) spans two chunks
    {
      EXPECT_LT(streamed.back().t_ns / 1000000, chunk.front().t_ns / 1000000);
    }
    streamed.insert(streamed.end(), chunk.begin(), chunk.end());
    ++chunks;
  });
  EXPECT_GE(chunks, 4);
  EXPECT_TRUE(parts.events.empty());
  EXPECT_EQ(parts.event_count, whole.events.size());
  EXPECT_EQ(streamed, whole.events);
  EXPECT_GE(whole.events.front().t_ns, 12345600);
}

TEST(Dataset, FileScenarioPlaysBackAGroundTruth)
{
  const SimConfig c = resolveSimConfig("linear", YAML::Node(), 1, 0.3);
  const std::string d = tempDir("file");
  const SimulationOutput out = runSimulation(c);
  writeDataset(d, c, out);
  YAML::Node over;
  over["trajectory"]["file"]["path"] = d + "/groundtruth.txt";
  const SimConfig f = resolveSimConfig("file", over, 1);
  EXPECT_NEAR(f.duration, 0.3, 1e-9);
  const auto traj = makeTrajectory(f);
  const auto ref = makeTrajectory(c);
  for (double t = 0; t < 0.3; t += 0.0123)
    EXPECT_LT((traj->poseAt(t).p_world_camera() - ref->poseAt(t).p_world_camera()).norm(), 1e-6);
  std::filesystem::remove_all(d);
}
