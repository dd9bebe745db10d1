// SilentSideCheck: a projected side that moves across the image without events, while a side of
// its polygon moves and fires and events no side explains arrive near the polygon, is where no
// edge is (known answers on hand-made projections).
#include <dvs_line_tracker/silent_side_check.h>

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

using namespace dvs_line_tracker;

namespace
{
/// Event time between the checks: 20 ms, so that each takes a snapshot (kSnapshotS) and
/// kPersistChecks snapshots (8) outlast kPersistS.
constexpr int64_t kCheckNs = 20000000;

ProjectedSegment segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double visible_fraction = 1.0)
{
  ProjectedSegment s;
  s.set(a, b);
  s.in_front = true;
  s.visible = true;
  s.visible_length = visible_fraction * s.length;
  return s;
}

/// Two horizontal sides of 40 px of one polygon, 40 px apart. Per check, side i is
/// `offset(i, check)` px down and receives `events(i)` attributed events, and `unexplained`
/// events no side explains arrive at `where` (between the sides: near the polygon).
struct Scenario
{
  std::function<double(int, int)> offset = [](int, int c) { return 0.5 * c; };
  std::function<int(int)> events = [](int i) { return i == 0 ? 20 : 0; };
  int unexplained = 20;
  Eigen::Vector2d where = Eigen::Vector2d(30, 45);
  double ratio = 0.1;
  int checks = 3 * (SilentSideCheck::kSpanChecks + SilentSideCheck::kPersistChecks);
  int64_t check_ns = kCheckNs;
};

/// The first reason given (or "").
std::string run(const Scenario& s)
{
  SilentSideCheck check(2, {{0, 1}}, s.ratio);
  for (int c = 0; c < s.checks; ++c)
  {
    std::vector<ProjectedSegment> projected;
    for (int i = 0; i < 2; ++i)
    {
      const double y = 20.0 + 40.0 * i + s.offset(i, c);
      projected.push_back(segment({10, y}, {50, y}));
    }
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < s.events(i); ++k)
        check.countAttributed(i);
    for (int k = 0; k < s.unexplained; ++k)
      check.countUnexplained(s.where + Eigen::Vector2d(0, 0.5 * c), projected);
    const std::string reason = check.check(projected, c * s.check_ns);
    if (!reason.empty())
      return reason;
  }
  return "";
}
}  // namespace

TEST(SilentSideCheck, SweptAreaOfATranslationAndOfATurn)
{
  const ProjectedSegment before = segment({0, 0}, {10, 0});
  // Moved 2 px along its normal: a 10 x 2 rectangle.
  EXPECT_NEAR(sweptArea(before, segment({0, 2}, {10, 2})), 20.0, 1e-9);
  EXPECT_NEAR(sweptArea(before, segment({0, -2}, {10, -2})), 20.0, 1e-9);
  // Turned about its middle, the ends 1 px either way: two triangles of 5 x 1 / 2.
  EXPECT_NEAR(sweptArea(before, segment({0, -1}, {10, 1})), 5.0, 1e-2);
  // Only half of it in view: half the area.
  EXPECT_NEAR(sweptArea(before, segment({0, 2}, {10, 2}, 0.5)), 10.0, 1e-9);
  // Moved along itself: nothing swept.
  EXPECT_NEAR(sweptArea(before, segment({3, 0}, {13, 0})), 0.0, 1e-9);
}

TEST(SilentSideCheck, ASideMovingWithoutEventsWhileItsEdgeFiresElsewhereIsNoEdge)
{
  // Both sides move 0.5 px per check; side 0 fires 20 events per check, side 1 none, and 20
  // unexplained events per check arrive between them.
  Scenario s;
  const std::string reason = run(s);
  EXPECT_NE(reason.find("map segment 1"), std::string::npos) << reason;
  EXPECT_NE(reason.find("no edge is where the pose puts it"), std::string::npos) << reason;
  // Half the density of the other side is an edge (a weaker or partly occluded one).
  Scenario weaker = s;
  weaker.events = [](int i) { return i == 0 ? 20 : 10; };
  EXPECT_EQ(run(weaker), "");
  // Off: no reason.
  Scenario off = s;
  off.ratio = 0;
  EXPECT_EQ(run(off), "");
}

TEST(SilentSideCheck, AnOccludedSideIsNoWrongPose)
{
  // Side 1 silent, but nothing unexplained arrives (its edge fires nowhere in view: hidden) ...
  Scenario hidden;
  hidden.unexplained = 0;
  EXPECT_EQ(run(hidden), "");
  // ... or what arrives is far from the polygon (another object, 90 px below its lower side).
  Scenario elsewhere;
  elsewhere.where = Eigen::Vector2d(30, 150);
  EXPECT_EQ(run(elsewhere), "");
  // Too little of it to say (a quarter of what the side should have drawn).
  Scenario few;
  few.unexplained = 5;
  EXPECT_EQ(run(few), "");
}

TEST(SilentSideCheck, ASideThatDoesNotMoveAcrossTheImageNeedNotFire)
{
  // Side 1 still (an edge moving along itself fires nothing) or jittering by +-0.6 px (the
  // estimate's noise: the net motion over the span counts, not the sum of the jitter).
  Scenario still;
  still.offset = [](int i, int c) { return i == 0 ? 0.5 * c : 0.0; };
  EXPECT_EQ(run(still), "");
  Scenario jitter;
  jitter.offset = [](int i, int c) { return i == 0 ? 0.5 * c : (c % 2 ? 0.6 : -0.6); };
  EXPECT_EQ(run(jitter), "");
}

TEST(SilentSideCheck, TheSilenceMustLast)
{
  // Checks 1 ms apart (a fast scene): snapshots are taken kSnapshotS apart, and the silence
  // must last kPersistS of event time (a flip's lag passes, a wrong pose stays).
  Scenario quick;
  quick.check_ns = 1000000;
  quick.checks = SilentSideCheck::kSpanChecks + SilentSideCheck::kPersistChecks;
  EXPECT_EQ(run(quick), "");
  quick.checks = 300;
  EXPECT_NE(run(quick).find("map segment 1"), std::string::npos);
}

TEST(SilentSideCheck, NoReferenceNoVerdict)
{
  // Neither side fires (a camera pausing, or too few events to compare): nothing is judged.
  Scenario none;
  none.events = [](int) { return 0; };
  EXPECT_EQ(run(none), "");
  // Sides of different polygons are not compared with each other.
  SilentSideCheck check(2, {{0}, {1}}, 0.1);
  std::string reason;
  for (int c = 0; c < 3 * (SilentSideCheck::kSpanChecks + SilentSideCheck::kPersistChecks) && reason.empty(); ++c)
  {
    const std::vector<ProjectedSegment> projected{segment({10, 20.0 + 0.5 * c}, {50, 20.0 + 0.5 * c}),
                                                  segment({10, 60.0 + 0.5 * c}, {50, 60.0 + 0.5 * c})};
    for (int k = 0; k < 20; ++k)
    {
      check.countAttributed(0);
      check.countUnexplained({30, 45.0 + 0.5 * c}, projected);
    }
    reason = check.check(projected, c * kCheckNs);
  }
  EXPECT_EQ(reason, "");
}

TEST(SilentSideCheck, RestartForgetsTheSpan)
{
  SilentSideCheck check(2, {}, 0.1);
  const auto step = [&](int c) {
    const std::vector<ProjectedSegment> projected{segment({10, 20.0 + 0.5 * c}, {50, 20.0 + 0.5 * c}),
                                                  segment({10, 60.0 + 0.5 * c}, {50, 60.0 + 0.5 * c})};
    for (int k = 0; k < 20; ++k)
    {
      check.countAttributed(0);
      check.countUnexplained({30, 45.0 + 0.5 * c}, projected);
    }
    return check.check(projected, c * kCheckNs);
  };
  // Side 1 moves without events for one check less than a verdict needs; after a restart (a new
  // track) its history is gone: the verdict needs a full span and kPersistChecks checks again.
  const int to_verdict = SilentSideCheck::kSpanChecks + SilentSideCheck::kPersistChecks;
  for (int c = 0; c < to_verdict - 1; ++c)
    EXPECT_EQ(step(c), "") << c;
  check.restart();
  int c = 0;
  std::string reason;
  while (reason.empty() && c < 4 * to_verdict)
    reason = step(100 + c++);
  EXPECT_EQ(c, to_verdict);
  EXPECT_NE(reason.find("map segment 1"), std::string::npos) << reason;
  // Out-of-range segment indices are ignored.
  check.countAttributed(-1);
  check.countAttributed(2);
}
