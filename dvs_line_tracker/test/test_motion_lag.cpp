// The vision estimate's lag behind a moving camera (motion_lag.h): known answers.
#include <dvs_line_tracker/motion_lag.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

namespace dvs_line_tracker
{
namespace
{
constexpr double kRate = 1000.0 * M_PI / 180.0;  // rad/s about the camera's y axis
constexpr double kSpeed = 2.0;                   // m/s along the world x axis
constexpr double kEventsPerSecond = 1e6;         // attributed

/// The camera at time t of a constant turn and translation.
Pose cameraAt(double t)
{
  return Pose::fromWorldCamera(Eigen::Matrix3d(Eigen::AngleAxisd(kRate * t, Eigen::Vector3d::UnitY())),
                               Eigen::Vector3d(kSpeed * t, 0, -2.0));
}

/// Samples every `step_s` (each event after the first 1 ms of a sample counts) for `duration_s`.
void feed(MotionLag& lag, double t0, double duration_s, double step_s = 1e-4)
{
  for (double t = t0; t <= t0 + duration_s + 1e-12; t += step_s)
    lag.sample(static_cast<int64_t>(std::llround(t * 1e9)), cameraAt(t),
               static_cast<uint64_t>(std::llround(t * kEventsPerSecond)));
}
}  // namespace

TEST(MotionLag, VarianceIsTheRateTimesHalfTheBuffersSpanSquared)
{
  MotionLag lag;
  feed(lag, 0.0, 0.010);
  // 4 visible segments x 35 events at 1 M events/s: the buffers span 140 us, half of it 70 us.
  const double half_span = 35.0 * 4 / kEventsPerSecond / 2;
  double w = 0, v = 0, span = 0;
  ASSERT_TRUE(lag.motion(4, 35, w, v, span));
  EXPECT_NEAR(w, kRate, 1e-6 * kRate);
  EXPECT_NEAR(v, kSpeed, 1e-6 * kSpeed);
  EXPECT_NEAR(span, 2 * half_span, 1e-3 * span);
  const Matrix6d c = lag.covariance(4, 35);
  for (int a = 0; a < 3; ++a)
  {
    EXPECT_NEAR(std::sqrt(c(a, a)), kRate * half_span, 1e-3 * kRate * half_span) << "rotation axis " << a;
    EXPECT_NEAR(std::sqrt(c(3 + a, 3 + a)), kSpeed * half_span, 1e-3 * kSpeed * half_span) << "position axis " << a;
  }
  // Diagonal, and twice the visible segments (the same event rate) fill the buffers in twice the time.
  EXPECT_EQ((c - Matrix6d(c.diagonal().asDiagonal())).norm(), 0.0);
  EXPECT_NEAR(lag.covariance(8, 35)(0, 0), 4 * c(0, 0), 1e-6 * c(0, 0));
  // The attributed event rate over the same window.
  EXPECT_NEAR(lag.attributedRate(), kEventsPerSecond, 1e-3 * kEventsPerSecond);
}

TEST(MotionLag, AttributedRateIsUnknownUntilFiveMillisecondsOfSamples)
{
  MotionLag lag;
  EXPECT_LT(lag.attributedRate(), 0.0) << "no sample";
  feed(lag, 0.0, 0.003);
  EXPECT_LT(lag.attributedRate(), 0.0) << "3 ms of samples";
  feed(lag, 0.0031, 0.003);
  EXPECT_NEAR(lag.attributedRate(), kEventsPerSecond, 1e-3 * kEventsPerSecond) << "6 ms of samples";
  // 30 attributed events per millisecond: 30,000 per second.
  MotionLag slow;
  for (int k = 0; k <= 10; ++k)
    slow.sample(k * 1000000, cameraAt(0), static_cast<uint64_t>(k) * 30);
  EXPECT_NEAR(slow.attributedRate(), 30000.0, 1e-6);
  // No event attributed over the window: not known (not zero).
  MotionLag none;
  for (int k = 0; k <= 10; ++k)
    none.sample(k * 1000000, cameraAt(0), 5);
  EXPECT_LT(none.attributedRate(), 0.0);
}

TEST(MotionLag, NothingIsAddedUntilTheMotionIsKnown)
{
  MotionLag lag;
  EXPECT_EQ(lag.covariance(4, 35).norm(), 0.0) << "no sample";
  feed(lag, 0.0, 0.003);
  EXPECT_EQ(lag.covariance(4, 35).norm(), 0.0) << "3 ms of samples: less than the 5 ms the rate needs";
  feed(lag, 0.0031, 0.003);
  EXPECT_GT(lag.covariance(4, 35).norm(), 0.0) << "6 ms of samples";
  EXPECT_EQ(lag.covariance(0, 35).norm(), 0.0) << "no segment in view";
  lag.reset();
  EXPECT_EQ(lag.covariance(4, 35).norm(), 0.0) << "after a reset (a new track)";
  EXPECT_LT(lag.attributedRate(), 0.0) << "after a reset";
  // Two samples a second apart say nothing about the current motion.
  lag.sample(0, cameraAt(0), 0);
  lag.sample(1000000000, cameraAt(1), 1000);
  EXPECT_EQ(lag.covariance(4, 35).norm(), 0.0);
  // A still camera adds nothing.
  MotionLag still;
  for (int k = 0; k <= 10; ++k)
    still.sample(k * 1000000, cameraAt(0), static_cast<uint64_t>(k) * 1000);
  EXPECT_EQ(still.covariance(4, 35).norm(), 0.0);
}
}  // namespace dvs_line_tracker
