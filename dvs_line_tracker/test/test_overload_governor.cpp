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
    g.tracked(1000, 4e-3);  // the tracker became 4x slower (a dense scene)
  EXPECT_NEAR(g.secondsPerEvent(), 4e-6, 1e-8);
  g.tracked(0, 1.0);  // nothing tracked: no information
  g.tracked(10, -1);  // a clock going back: ignored
  EXPECT_NEAR(g.secondsPerEvent(), 4e-6, 1e-8);
}

TEST(OverloadGovernor, InitialisingAndTrackingCostsAreKeptApart)
{
  // An initialisation costs several times a tracked event: a tracking stride made from it
  // skipped far more than needed right after the start.
  OverloadParams p;
  p.max_latency_s = 0.01;
  OverloadGovernor g(p);
  for (int i = 0; i < 10; ++i)
    g.tracked(1000, 5e-3, true);  // 5 us per event while initialising
  EXPECT_DOUBLE_EQ(g.secondsPerEventInitialising(), 5e-6);
  EXPECT_EQ(g.secondsPerEvent(), 0.0);
  EXPECT_EQ(g.strideFor(100000, true), 50);  // 0.5 s of initialisation work queued
  EXPECT_EQ(g.strideFor(100000), 1);         // tracking's cost not measured yet: every event
  g.tracked(1000, 0.5e-3);                   // 0.5 us per tracked event
  EXPECT_DOUBLE_EQ(g.secondsPerEvent(), 0.5e-6);
  EXPECT_DOUBLE_EQ(g.secondsPerEventInitialising(), 5e-6);
  EXPECT_EQ(g.strideFor(100000), 5);
  EXPECT_EQ(g.strideFor(100000, true), 50);
}

TEST(OverloadGovernor, APacketOfFewEventsDelayedByTheSchedulerHardlyMovesTheCost)
{
  // 0.4 us per event in packets of 700, then 10 events that took 0.44 ms (the thread was
  // descheduled): weighted by its events, that packet moves the cost by a few per cent, and the
  // stride for a queue of 1 M events in a 0.1 s budget stays at 5 (a running mean per packet,
  // weight 0.2, made the cost 9 us and the stride the maximum, 64).
  OverloadGovernor g;
  for (int i = 0; i < 20; ++i)
    g.tracked(700, 700 * 0.4e-6);
  EXPECT_NEAR(g.secondsPerEvent(), 0.4e-6, 1e-12);
  g.tracked(10, 0.44e-3);
  EXPECT_LT(g.secondsPerEvent(), 0.5e-6);
  EXPECT_LE(g.strideFor(1000000), 5);
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
  EXPECT_EQ(g.stats().events_skipped_whole, 2000u);
  // A packet taken or skipped whole does not count as tracked with a stride.
  OverloadParams p;
  p.max_latency_s = 0.01;
  OverloadGovernor s(p);
  s.tracked(1000, 0.001, true);  // 1 us per event, initialising
  s.tracked(1000, 0.001);        // and tracking
  ASSERT_EQ(s.strideFor(100000, true), 10);
  EXPECT_FALSE(s.skipWholePacket(10, 1000));
  EXPECT_EQ(s.stats().packets_strided, 0u);
  ASSERT_EQ(s.strideFor(100000, true), 10);
  EXPECT_TRUE(s.skipWholePacket(10, 1000));
  EXPECT_EQ(s.stats().packets_strided, 0u);
  EXPECT_EQ(s.stats().packets_skipped, 1u);
  EXPECT_EQ(s.stats().events_skipped_whole, 1000u);
  ASSERT_EQ(s.strideFor(100000), 10);  // tracked with the stride: counted
  EXPECT_EQ(s.stats().packets_strided, 1u);
  // The first packet at a stride is taken (a single packet is never lost).
  OverloadGovernor h;
  EXPECT_FALSE(h.skipWholePacket(64, 10));
  EXPECT_TRUE(h.skipWholePacket(64, 10));
  EXPECT_EQ(h.stats().events_skipped, 10u);
}
