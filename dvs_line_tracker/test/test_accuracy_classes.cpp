// The accuracy classes of issue 15 (benchmark_accuracy): every class resolves to a valid
// simulation with the map it is meant to have, an unknown class is named, and the low-contrast
// class is tracked end to end on the software DVS, the IMU fused on a slow class helps; the
// benchmarks' whole-number options.
#include "accuracy_classes.h"
#include "benchmark_tool.h"

#include <gtest/gtest.h>

#include <set>

using namespace dvs_line_tracker;

TEST(AccuracyClasses, EveryClassResolvesWithItsMap)
{
  std::set<std::string> keys;
  for (const auto& c : accuracyClasses())
  {
    SCOPED_TRACE(c.key);
    EXPECT_TRUE(keys.insert(c.key).second) << "duplicate key";
    const dvs_screen_sim::SimConfig config = accuracyConfig(c, 1);
    EXPECT_EQ(config.scenario, c.scenario);
    EXPECT_GE(config.duration, 1.5);
    const LineMap map = mapOfScene(config.scene, c.key);
    EXPECT_EQ(map.polygons.size(), c.key == "twosquares" ? 2u : 1u);
    EXPECT_EQ(map.segments.size(), c.key == "twosquares" ? 8u : 4u);
  }
  EXPECT_EQ(accuracyConfig(accuracyClass("davis346far"), 1).camera.intrinsics().width, 346);
  EXPECT_EQ(accuracyConfig(accuracyClass("flip23"), 1).scenario, "flip");
}

TEST(AccuracyClasses, UnknownClassIsNamedWithTheKnownOnes)
{
  try
  {
    accuracyClass("flip99");
    FAIL() << "no exception";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("'flip99'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("flip23"), std::string::npos) << e.what();
  }
}

// Grey square on white (contrast ratio 3, half the events per edge crossing) on a 1200 deg/s flip
// at 1.8 m: tracked throughout. Seeds 1-5 measure 2.5-2.7 cm RMS (BENCHMARKS.md); the bound
// leaves room for the simulator's randomness, not for a regression to the constant offset
// (3.2 cm).
TEST(AccuracyClasses, LowContrastFlipIsTracked)
{
  const AccuracyScene scene = simulateAccuracyScene(accuracyClass("contrast3"), 1);
  const AccuracyRun run = runAccuracyScene(scene, LineTrackerParams());
  EXPECT_GE(run.accuracy.first_estimate_s, 0.0);
  EXPECT_DOUBLE_EQ(run.accuracy.trackedFraction(), 1.0);
  EXPECT_LT(run.accuracy.rms_position_m, 0.030);
  EXPECT_EQ(run.stats.losses, 0u);
}

// A slow hand-held-like camera 1.8-2.6 m from a 0.9 m square, with its IMU fused: the filter's
// vision measurement is where the buffered events put the camera, so a first pose's error in the
// weak lateral / rotation pair is corrected as fast as the vision corrects it, and the gyroscope
// then steadies the pair. Seeds 1-3 measure 2.1 / 3.2 / 1.1 cm with the IMU against 2.9 / 3.9 /
// 1.8 cm without (BENCHMARKS.md, fortieth session); with the tracker's damped pose as the
// measurement the filter held the first pose's error: 6.7 / 13.7 / 1.9 cm, 28 % of seed 2 tracked.
TEST(AccuracyClasses, TheImuDoesNotHoldASlowCameraAtItsFirstPosesError)
{
  for (const uint64_t seed : {1u, 2u, 3u})
  {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const AccuracyScene scene = simulateAccuracyScene(accuracyClass("onesquare09"), seed);
    ASSERT_GT(scene.output.imu.size(), 2000u);
    const AccuracyRun vision = runAccuracyScene(scene, LineTrackerParams());
    const AccuracyRun fused = runAccuracyScene(scene, LineTrackerParams(), nullptr, true);
    ASSERT_GE(fused.accuracy.first_estimate_s, 0.0);
    EXPECT_TRUE(fused.imu_status == "OK" || fused.imu_status == "GYRO_ONLY") << fused.imu_status;
    EXPECT_LT(fused.accuracy.rms_position_m, vision.accuracy.rms_position_m)
        << "vision alone " << vision.accuracy.rms_position_m;
    EXPECT_GE(fused.accuracy.trackedFraction(), 0.99);
  }
}

TEST(BenchmarkTool, WholeNumberOptionsTakeOnlyDecimalsInRange)
{
  int v = -7;
  EXPECT_TRUE(parseIntInRange("5", 1, 1000, v));
  EXPECT_EQ(v, 5);
  EXPECT_TRUE(parseIntInRange("1000", 1, 1000, v));
  EXPECT_EQ(v, 1000);
  for (const char* bad : {"", "0", "1001", "x", "5x", "2.5", "-3", " "})
  {
    v = -7;
    EXPECT_FALSE(parseIntInRange(bad, 1, 1000, v)) << "'" << bad << "'";
    EXPECT_EQ(v, -7) << "'" << bad << "' changed the value";
  }
}
