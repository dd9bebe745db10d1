// OverloadGovernor: first the batched solve, then the stride that works a queue off within the
// latency budget, from the measured cost per event; back to every event's own solve with
// hysteresis; the counters of what was skipped or dropped.
#include <dvs_line_tracker/overload_governor.h>

#include <gtest/gtest.h>

using namespace dvs_line_tracker;

namespace
{
/// The governor's action for `queued` events is (solve_every, stride).
void expectAction(OverloadGovernor& g, size_t queued, int solve_every, int stride)
{
  const OverloadAction a = g.actionFor(queued);
  EXPECT_EQ(a.solve_every, solve_every) << queued << " queued";
  EXPECT_EQ(a.stride, stride) << queued << " queued";
}
}  // namespace

TEST(OverloadGovernor, EveryEventUntilTheCostIsKnown)
{
  OverloadGovernor g;
  expectAction(g, 1000000, 1, 1);
  EXPECT_EQ(g.stats().packets_batched + g.stats().packets_strided, 0u);
}

TEST(OverloadGovernor, BatchedSolveFirstThenTheStrideThatWorksTheQueueOff)
{
  OverloadParams p;
  p.max_latency_s = 0.005;
  p.batch_solve_every = 4;
  OverloadGovernor g(p);
  g.tracked(1000, 1000 * 1e-6);  // 1 us per event
  EXPECT_DOUBLE_EQ(g.secondsPerEvent(), 1e-6);
  // 4,000 queued events take 4 ms: every event, its own solve.
  expectAction(g, 4000, 1, 1);
  // 12,000 take 12 ms: the batched solve first, every event still tracked.
  expectAction(g, 12000, 4, 1);
  EXPECT_TRUE(g.batched());
  // Batched and still behind (0.5 us per event measured now, 24,000 queued: 12 ms): every
  // third event as well.
  for (int i = 0; i < 50; ++i)
    g.tracked(1000, 1000 * 0.5e-6);
  expectAction(g, 24000, 4, 3);
  EXPECT_EQ(g.stats().last.stride, 3);
  EXPECT_EQ(g.stats().packets_strided, 1u);
  EXPECT_EQ(g.stats().packets_batched, 2u);
  // Bounded by max_stride.
  EXPECT_EQ(g.actionFor(100000000).stride, p.max_stride);
  EXPECT_EQ(g.stats().max_stride_used, p.max_stride);
  // Caught up, but not by far (2,000 queued: 1 ms, a fifth of the budget at the batched cost, 2
  // at the full one): batched still, every event.
  expectAction(g, 3000, 4, 1);
  // Far below (2 ms at the full cost): every event's own solve again.
  expectAction(g, 2000, 1, 1);
  EXPECT_FALSE(g.batched());
}

TEST(OverloadGovernor, WithoutBatchingTheStrideAlone)
{
  OverloadParams p;
  p.max_latency_s = 0.005;
  p.batch_solve_every = 1;
  OverloadGovernor g(p);
  g.tracked(1000, 1000 * 1e-6);
  expectAction(g, 12000, 1, 3);
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

TEST(OverloadGovernor, ZeroLatencyBudgetNeverDegrades)
{
  OverloadParams p;
  p.max_latency_s = 0;
  OverloadGovernor g(p);
  g.tracked(10, 1.0);
  expectAction(g, 1000000, 1, 1);
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
