// The sub-pixel edge position model (edge_run_model.h): known answers of the offsets, the
// per-pixel run bookkeeping, and the learning of the contrast threshold from run lengths.
#include <dvs_line_tracker/edge_run_model.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace dvs_line_tracker;

TEST(EdgeRunModel, OffsetsOfTheRunIndexKnownAnswers)
{
  // rho = 9, C = 0.3. First ON event: bright fraction (e^0.45 - 1) / 8 = 0.0710 -> the pixel is
  // 92.9 % dark, the edge 0.429 px from its centre towards the bright side.
  EXPECT_NEAR(EdgeRunModel::runOffset(true, 1, 0.3, 9.0), 0.5 - std::expm1(0.45) / 8.0, 1e-12);
  EXPECT_NEAR(EdgeRunModel::runOffset(true, 1, 0.3, 9.0), 0.4290, 1e-4);
  // First OFF event: dark fraction (1 - e^-0.45) / (8/9) = 0.4077 -> -0.092 px.
  EXPECT_NEAR(EdgeRunModel::runOffset(false, 1, 0.3, 9.0), -0.0923, 1e-4);
  // The offsets sweep across the pixel: ON from the bright side's far end towards the dark
  // side (monotonically decreasing), OFF the other way; saturated at -0.5 (fully dark) / +0.5.
  for (int k = 1; k < 12; ++k)
  {
    EXPECT_LT(EdgeRunModel::runOffset(true, k + 1, 0.3, 9.0), EdgeRunModel::runOffset(true, k, 0.3, 9.0) + 1e-12);
    EXPECT_GT(EdgeRunModel::runOffset(false, k + 1, 0.3, 9.0), EdgeRunModel::runOffset(false, k, 0.3, 9.0) - 1e-12);
  }
  EXPECT_DOUBLE_EQ(EdgeRunModel::runOffset(true, 20, 0.3, 9.0), -0.5);
  EXPECT_DOUBLE_EQ(EdgeRunModel::runOffset(false, 20, 0.3, 9.0), 0.5);
}

TEST(EdgeRunModel, FullSweepsFollowTheRunTable)
{
  EdgeRunModelParams params;
  params.contrast_threshold = 0.3;
  EdgeRunModel model(4, 4, params);
  EXPECT_DOUBLE_EQ(model.threshold(), 0.3);
  // Pixel (1, 2): a dark edge sweeps in (7 OFF events: a full sweep, ln 9 / 0.3 = 7.3 steps),
  // then out again (ON): each run restarts from saturation and follows the table.
  for (int k = 1; k <= 6; ++k)
    EXPECT_NEAR(model.update(1, 2, false), EdgeRunModel::runOffset(false, k, 0.3, 9.0), 1e-6) << k;
  // Another pixel does not disturb it.
  EXPECT_NEAR(model.update(2, 1, true), EdgeRunModel::runOffset(true, 1, 0.3, 9.0), 1e-6);
  model.update(1, 2, false);
  for (int k = 1; k <= 6; ++k)
    EXPECT_NEAR(model.update(1, 2, true), EdgeRunModel::runOffset(true, k, 0.3, 9.0), 1e-6) << k;
  EXPECT_EQ(model.completedRuns(), 1u);  // the 7-event OFF run
  EXPECT_DOUBLE_EQ(model.meanRunLength(), 7.0);
  // A very long run saturates (the pixel fully bright: the edge half a pixel beyond its centre
  // on the dark side, up to the half step of the reference level), no overflow.
  double last = 1.0;
  for (int i = 0; i < 300; ++i)
  {
    const double offset = model.update(0, 0, true);
    EXPECT_LE(offset, last + 1e-12);
    last = offset;
  }
  EXPECT_NEAR(last, 0.5 - std::expm1(std::log(9.0) - 0.15) / 8.0, 1e-6);  // -0.34 px
}

TEST(EdgeRunModel, APartialSweepContinuesFromItsLevel)
{
  EdgeRunModelParams params;
  params.contrast_threshold = 0.3;
  EdgeRunModel model(4, 4, params);
  // Three OFF events from a bright pixel (the edge enters it), then the edge turns back: the
  // first ON event fires one step above the last OFF level, i.e. two steps below the bright
  // saturation -- not at the first ON level of a dark pixel (which would put the edge 0.43 px
  // the other way).
  for (int k = 0; k < 3; ++k)
    model.update(3, 3, false);
  const double level = std::log(9.0) - 0.15 - 3 * 0.3 + 0.3;
  const double turned_back = model.update(3, 3, true);
  EXPECT_NEAR(turned_back, 0.5 - std::expm1(level) / 8.0, 1e-6);  // +0.09 px
  EXPECT_GT(EdgeRunModel::runOffset(true, 1, 0.3, 9.0) - turned_back, 0.3);
  // And back again: one step down from there.
  EXPECT_NEAR(model.update(3, 3, false), 0.5 - std::expm1(level - 0.3) / 8.0, 1e-6);
}

TEST(EdgeRunModel, LearnsTheThresholdFromTheRunLengths)
{
  EdgeRunModelParams params;  // contrast_threshold 0: learn
  params.min_learning_runs = 100;
  // Until enough runs were completed: the prior threshold; without a prior, the constant offset.
  {
    EdgeRunModel with_prior(8, 8, params);
    EXPECT_DOUBLE_EQ(with_prior.threshold(), params.prior_threshold);
    EXPECT_FALSE(with_prior.thresholdLearned());
    EXPECT_NEAR(with_prior.update(5, 5, true), EdgeRunModel::runOffset(true, 1, params.prior_threshold, 9.0), 1e-6);
  }
  params.prior_threshold = 0;
  EdgeRunModel model(64, 64, params);
  EXPECT_DOUBLE_EQ(model.threshold(), 0.0);
  EXPECT_DOUBLE_EQ(model.update(5, 5, true), params.constant_offset_px);
  // Full sweeps of a sensor with C = 0.2 over edges of contrast 9: ln 9 / 0.2 = 11.0 steps,
  // i.e. runs of 10 or 11 events (mean 10.5 = ln(rho)/C - 1/2), alternating polarity; plus
  // short runs of 1-2 events (noise, partial sweeps) that are not counted.
  int pixel = 0;
  for (int sweep = 0; sweep < 400; ++sweep)
  {
    const int x = pixel % 64, y = pixel / 64;
    ++pixel;
    const int length = sweep % 2 ? 10 : 11;
    for (int polarity = 0; polarity < 2; ++polarity)
      for (int i = 0; i < length; ++i)
        model.update(x, y, polarity == 1);
    model.update(x, y, false);  // ends the ON run
    model.update(x, y, true);   // a 1-event OFF run (not counted) ends with this
  }
  EXPECT_GT(model.completedRuns(), 700u);
  EXPECT_NEAR(model.meanRunLength(), 10.5, 1e-9);
  EXPECT_NEAR(model.threshold(), std::log(9.0) / 11.0, 1e-9);
  EXPECT_TRUE(model.thresholdLearned());
  // A fixed threshold is never replaced.
  params.contrast_threshold = 0.45;
  EdgeRunModel fixed(8, 8, params);
  for (int i = 0; i < 5000; ++i)
    fixed.update(i % 8, (i / 8) % 8, (i / 64) % 2 == 0);
  EXPECT_DOUBLE_EQ(fixed.threshold(), 0.45);
}

TEST(EdgeRunModel, DisabledGivesTheConstantOffset)
{
  EdgeRunModelParams params;
  params.enabled = false;
  params.contrast_threshold = 0.3;
  params.constant_offset_px = 0.2;
  EdgeRunModel model(8, 8, params);
  for (int i = 0; i < 3000; ++i)
    EXPECT_DOUBLE_EQ(model.update(i % 8, 3, i % 7 < 3), 0.2);
  EXPECT_DOUBLE_EQ(model.threshold(), 0.0);
}
