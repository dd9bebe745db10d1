// NeighbourActivity (neighbour_activity.h): known answers for support, the horizon, the border
// and pixels outside the sensor; background noise supported at its binomial share; the
// same-polarity variant counts only neighbours of the event's polarity, and admits noise at the
// binomial share of half the rate.
#include <dvs_line_tracker/neighbour_activity.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

using dvs_line_tracker::NeighbourActivity;

TEST(NeighbourActivity, SupportCountsTheEightNeighbours)
{
  NeighbourActivity a(32, 32, 100, 2);
  EXPECT_FALSE(a.add(10, 10));  // nothing before it
  EXPECT_FALSE(a.add(11, 10));  // one neighbour
  EXPECT_FALSE(a.add(13, 10));  // two pixels away from (11, 10): no neighbour
  EXPECT_TRUE(a.add(10, 11));   // (10, 10) and (11, 10)
  EXPECT_TRUE(a.add(12, 11));   // (11, 10) and (13, 10)
  EXPECT_FALSE(a.add(20, 20));  // its own earlier event is no neighbour:
  EXPECT_FALSE(a.add(20, 20));
  EXPECT_EQ(a.horizonEvents(), 100);
  a.reset();
  EXPECT_FALSE(a.add(11, 11));  // forgotten
}

TEST(NeighbourActivity, OnlyTheLatestHorizonEventsCount)
{
  NeighbourActivity a(32, 32, 3, 2);
  a.add(5, 5);  // event 1
  a.add(6, 5);  // event 2
  a.add(20, 20);
  a.add(25, 25);
  a.add(28, 3);                // event 5
  EXPECT_FALSE(a.add(5, 6));   // event 6: the latest 3 are events 3-5
  NeighbourActivity b(32, 32, 3, 2);
  b.add(5, 5);
  b.add(6, 5);
  b.add(20, 20);
  EXPECT_TRUE(b.add(5, 6));    // event 4: events 1-3 are the latest 3
}

TEST(NeighbourActivity, BorderAndOutsidePixels)
{
  NeighbourActivity a(32, 24, 2, 2);
  a.add(1, 0);
  a.add(0, 1);
  EXPECT_FALSE(a.add(-1, 0));  // outside: ignored, not counted
  EXPECT_FALSE(a.add(32, 5));
  EXPECT_FALSE(a.add(5, 24));
  EXPECT_TRUE(a.add(0, 0));    // the corner's neighbours (1, 0), (0, 1) still within the horizon of 2
  a.add(31, 22);
  EXPECT_FALSE(a.add(31, 23));  // the opposite corner: one neighbour
  EXPECT_TRUE(a.add(30, 23));   // (31, 22) and (31, 23)
}

TEST(NeighbourActivity, NoiseIsSupportedAtItsBinomialShare)
{
  // Uniform background events: within the horizon each neighbour fired with probability
  // q = 1 - exp(-horizon / pixels), so P(>= 2 of 8) = 1 - (1-q)^8 - 8 q (1-q)^7, whatever the
  // noise rate (the horizon is in events). 640x480 with the default scaled horizon: 2.2 %.
  const int w = 640, h = 480, horizon = 9375;
  NeighbourActivity a(w, h, horizon, 2);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> ux(0, w - 1), uy(0, h - 1);
  int supported = 0, counted = 0;
  for (int i = 0; i < 400000; ++i)
  {
    const bool s = a.add(ux(rng), uy(rng));
    if (i < 50000)
      continue;  // warm-up: the horizon filled many times over
    supported += s ? 1 : 0;
    ++counted;
  }
  const double q = 1 - std::exp(-static_cast<double>(horizon) / (w * h));
  const double expected = 1 - std::pow(1 - q, 8) - 8 * q * std::pow(1 - q, 7);
  EXPECT_NEAR(expected, 0.022, 0.001);
  EXPECT_NEAR(static_cast<double>(supported) / counted, expected, 0.1 * expected);
}

TEST(NeighbourActivity, SamePolarityCountsOnlyNeighboursOfTheEventsPolarity)
{
  NeighbourActivity blind(32, 32, 100, 2);
  NeighbourActivity same(32, 32, 100, 2, true);
  EXPECT_FALSE(blind.samePolarity());
  EXPECT_TRUE(same.samePolarity());
  for (NeighbourActivity* a : {&blind, &same})
  {
    a->add(10, 10, true);
    a->add(11, 10, false);
  }
  // (10, 11) has an ON and an OFF neighbour: two for the blind test, one of either polarity.
  EXPECT_TRUE(blind.add(10, 11, true));
  EXPECT_FALSE(same.add(10, 11, true));
  same.reset();
  same.add(10, 10, false);
  same.add(11, 10, false);
  EXPECT_TRUE(same.add(10, 11, false));  // two OFF neighbours
  EXPECT_FALSE(same.add(20, 20, true));
  // A pixel's latest event of each polarity is kept apart: an OFF event at (11, 10) after its ON
  // one leaves the ON one counting for ON events.
  same.reset();
  same.add(10, 10, true);
  same.add(11, 10, true);
  same.add(11, 10, false);
  EXPECT_TRUE(same.add(10, 11, true));
  // The horizon counts events of both polarities.
  NeighbourActivity short_horizon(32, 32, 2, 2, true);
  short_horizon.add(5, 5, true);
  short_horizon.add(6, 5, true);
  short_horizon.add(20, 20, false);  // pushes (5, 5) out of the latest 2
  EXPECT_FALSE(short_horizon.add(5, 6, true));
}

TEST(NeighbourActivity, SamePolarityAdmitsNoiseAtHalfTheRate)
{
  // Random polarities: each neighbour fired an event of the given polarity with probability
  // q = 1 - exp(-horizon / (2 pixels)) within the horizon.
  const int w = 128, h = 128, horizon = 1500;
  NeighbourActivity a(w, h, horizon, 2, true);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> ux(0, w - 1), uy(0, h - 1), up(0, 1);
  int supported = 0, counted = 0;
  for (int i = 0; i < 300000; ++i)
  {
    const bool s = a.add(ux(rng), uy(rng), up(rng) == 1);
    if (i < 30000)
      continue;
    supported += s ? 1 : 0;
    ++counted;
  }
  const double q = 1 - std::exp(-static_cast<double>(horizon) / (2.0 * w * h));
  const double expected = 1 - std::pow(1 - q, 8) - 8 * q * std::pow(1 - q, 7);
  EXPECT_NEAR(static_cast<double>(supported) / counted, expected, 0.1 * expected);
}

TEST(NeighbourActivity, RejectsABadConstruction)
{
  EXPECT_THROW(NeighbourActivity(0, 10, 5, 2), std::invalid_argument);
  EXPECT_THROW(NeighbourActivity(10, -1, 5, 2), std::invalid_argument);
  EXPECT_THROW(NeighbourActivity(10, 10, 0, 2), std::invalid_argument);
  EXPECT_THROW(NeighbourActivity(10, 10, 5, 0), std::invalid_argument);
}
