// OverloadGovernor: the stride that works a queue off within the latency budget, from the
// measured cost per event; the counters of what was skipped or dropped.
#include <dvs_line_tracker/overload_governor.h>

#include <gtest/gtest.h>

using namespace dvs_line_tracker;

TEST(OverloadGovernor, EveryEventUntilTheCostIsKnown)
{
  OverloadGovernor g;
  EXPECT_EQ(g.strideFor(1000000), 1);
  EXPECT_EQ(g.stats().packets_strided, 0u);
}

TEST(OverloadGovernor, StrideWorksTheQueueOffWithinTheBudget)
{
  OverloadParams p;
  p.max_latency_s = 0.005;
  OverloadGovernor g(p);
  g.tracked(1000, 1000 * 1e-6);  // 1 us per event
  EXPECT_DOUBLE_EQ(g.secondsPerEvent(), 1e-6);
  // 4,000 queued events take 4 ms: every event.
  EXPECT_EQ(g.strideFor(4000), 1);
  // 12,000 take 12 ms: every third event (4 ms).
  EXPECT_EQ(g.strideFor(12000), 3);
  EXPECT_EQ(g.stats().last_stride, 3);
  EXPECT_EQ(g.stats().packets_strided, 1u);
  // Bounded by max_stride.
  EXPECT_EQ(g.strideFor(100000000), p.max_stride);
  EXPECT_EQ(g.stats().max_stride_used, p.max_stride);
  // Caught up: every event again.
  EXPECT_EQ(g.strideFor(2000), 1);
}

TEST(OverloadGovernor, CostFollowsTheMeasurements)
{
  OverloadGovernor g;
  g.tracked(1000, 1e-3);
  for (int i = 0; i < 40; ++i)
    g.tracked(1000, 4e-3);  // the tracker became 4x slower (initialising)
  EXPECT_NEAR(g.secondsPerEvent(), 4e-6, 1e-8);
  g.tracked(0, 1.0);  // nothing tracked: no information
  g.tracked(10, -1);  // a clock going back: ignored
  EXPECT_NEAR(g.secondsPerEvent(), 4e-6, 1e-8);
}

TEST(OverloadGovernor, ZeroLatencyBudgetNeverSkips)
{
  OverloadParams p;
  p.max_latency_s = 0;
  OverloadGovernor g(p);
  g.tracked(10, 1.0);
  EXPECT_EQ(g.strideFor(1000000), 1);
}

TEST(OverloadGovernor, CountsWhatIsLeftOut)
{
  OverloadParams p;
  p.max_queued_events = 100;
  OverloadGovernor g(p);
  g.skipped(7);
  g.skipped(3);
  EXPECT_EQ(g.stats().events_skipped, 10u);
  EXPECT_FALSE(g.overQueueLimit(100));
  EXPECT_TRUE(g.overQueueLimit(101));
  g.dropped(50);
  EXPECT_EQ(g.stats().packets_dropped, 1u);
  EXPECT_EQ(g.stats().events_dropped, 50u);
}

TEST(OverloadGovernor, WhileInitialisingEveryStrideThPacketIsTakenWhole)
{
  OverloadGovernor g;
  // Stride 1: nothing skipped, and the packet phase does not move.
  for (int i = 0; i < 5; ++i)
    EXPECT_FALSE(g.skipWholePacket(1, 100));
  // Stride 3: one packet of three taken, the same share of the events as every 3rd event.
  int taken = 0;
  for (int i = 0; i < 30; ++i)
    taken += g.skipWholePacket(3, 100) ? 0 : 1;
  EXPECT_EQ(taken, 10);
  EXPECT_EQ(g.stats().packets_skipped, 20u);
  EXPECT_EQ(g.stats().events_skipped, 2000u);  // counted with the events a stride leaves out
  // A packet taken or skipped whole does not count as tracked with a stride.
  OverloadParams p;
  p.max_latency_s = 0.01;
  OverloadGovernor s(p);
  s.tracked(1000, 0.001);  // 1 us per event
  ASSERT_EQ(s.strideFor(100000, true), 10);
  EXPECT_FALSE(s.skipWholePacket(10, 1000));
  EXPECT_EQ(s.stats().packets_strided, 0u);
  ASSERT_EQ(s.strideFor(100000, true), 10);
  EXPECT_TRUE(s.skipWholePacket(10, 1000));
  EXPECT_EQ(s.stats().packets_strided, 0u);
  EXPECT_EQ(s.stats().packets_skipped, 1u);
  ASSERT_EQ(s.strideFor(100000), 10);  // tracked with the stride: counted
  EXPECT_EQ(s.stats().packets_strided, 1u);
  // The first packet at a stride is taken (a single packet is never lost).
  OverloadGovernor h;
  EXPECT_FALSE(h.skipWholePacket(64, 10));
  EXPECT_TRUE(h.skipWholePacket(64, 10));
  EXPECT_EQ(h.stats().events_skipped, 10u);
}
