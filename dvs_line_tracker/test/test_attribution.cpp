// Event attribution regions (thesis Fig. 4.5) and buffer replacement (Fig. 4.6).
#include <dvs_line_tracker/segment_attribution.h>

#include <gtest/gtest.h>

using namespace dvs_line_tracker;

namespace
{
// la: horizontal from (20,20) to (80,20); lb: vertical from (80,20) to (80,80): a corner at (80,20).
std::vector<ProjectedSegment> corner()
{
  std::vector<ProjectedSegment> s(2);
  s[0].set({20, 20}, {80, 20});
  s[1].set({80, 20}, {80, 80});
  s[0].visible = s[1].visible = true;
  return s;
}
}  // namespace

TEST(Attribution, DistancesFollowEquations42And43)
{
  ProjectedSegment s;
  s.set({10, 10}, {50, 10});
  EXPECT_DOUBLE_EQ(s.orthogonalDistance({30, 12}), 2.0);
  EXPECT_DOUBLE_EQ(s.parallelDistance({30, 12}), -20.0);  // between the ends: negative
  EXPECT_DOUBLE_EQ(s.parallelDistance({55, 10}), 5.0);    // beyond the end: positive
  EXPECT_DOUBLE_EQ(s.parallelDistance({4, 9}), 6.0);
}

TEST(Attribution, RegionsAtoD)
{
  const auto segs = corner();
  AttributionParams p;  // 2 px orthogonal, 10 px parallel
  int out[2];
  AttributionRegion r;
  // Single segment, far from the corner.
  ASSERT_EQ(attributeEvent({40, 21}, segs.data(), 2, p, out, &r), 1);
  EXPECT_EQ(out[0], 0);
  EXPECT_EQ(r, AttributionRegion::kSingle);
  // Region A: between the ends of la (x < 80), beyond the end of lb (y < 20), near both.
  ASSERT_EQ(attributeEvent({79, 19}, segs.data(), 2, p, out, &r), 1);
  EXPECT_EQ(out[0], 0);
  EXPECT_EQ(r, AttributionRegion::kOnlyFirst);
  // Region B: between the ends of lb, beyond la's end.
  ASSERT_EQ(attributeEvent({81, 21}, segs.data(), 2, p, out, &r), 1);
  EXPECT_EQ(out[0], 1);
  EXPECT_EQ(r, AttributionRegion::kOnlyFirst);
  // Region C: beyond both ends (outside the corner): both.
  ASSERT_EQ(attributeEvent({81, 19}, segs.data(), 2, p, out, &r), 2);
  EXPECT_EQ(r, AttributionRegion::kBoth);
  EXPECT_TRUE((out[0] == 0 && out[1] == 1) || (out[0] == 1 && out[1] == 0));
  // Region D: between the ends of both (inside the corner): none, the polygon must not shrink.
  EXPECT_EQ(attributeEvent({79, 21}, segs.data(), 2, p, out, &r), 0);
  EXPECT_EQ(r, AttributionRegion::kInsideBoth);
  // Too far: orthogonal > 2 px, or parallel > 10 px beyond the end.
  EXPECT_EQ(attributeEvent({40, 23}, segs.data(), 2, p, out, &r), 0);
  EXPECT_EQ(attributeEvent({9, 20}, segs.data(), 2, p, out, &r), 0);
  EXPECT_EQ(attributeEvent({11, 20}, segs.data(), 2, p, out, &r), 1);
}

TEST(Attribution, ThreeSegmentsInRangeDiscardAndInvisibleSegmentsAreIgnored)
{
  std::vector<ProjectedSegment> s(3);
  s[0].set({20, 20}, {80, 20});
  s[1].set({20, 21}, {80, 21});
  s[2].set({20, 22}, {80, 22});
  for (auto& x : s)
    x.visible = true;
  int out[2];
  EXPECT_EQ(attributeEvent({50, 21}, s.data(), 3, AttributionParams(), out), 0);
  s[2].visible = false;
  AttributionRegion r;
  // Now two in range, both between their ends: region D rule -> discarded.
  EXPECT_EQ(attributeEvent({50, 21}, s.data(), 3, AttributionParams(), out, &r), 0);
  EXPECT_EQ(r, AttributionRegion::kInsideBoth);
  s[1].visible = false;
  EXPECT_EQ(attributeEvent({50, 21}, s.data(), 3, AttributionParams(), out), 1);
  EXPECT_EQ(out[0], 0);
}

TEST(SegmentBuffer, NewEventReplacesTheClosestOldOne)
{
  ProjectedSegment seg;
  seg.set({0, 0}, {80, 0});
  SegmentBuffer b(8);  // spacing 10 px -> replacement threshold 5 px
  for (int i = 0; i < 8; ++i)
    b.insert({5.0 + 10 * i, 0.5}, seg);
  ASSERT_EQ(b.size(), 8);
  // A new event at x = 46 is 1 px from the stored event at 45: that one is replaced, not the
  // oldest (x = 5), which keeps the events spread along the segment (thesis Fig. 4.6b).
  const int slot = b.insert({46, -0.5}, seg);
  EXPECT_EQ(slot, 4);
  EXPECT_DOUBLE_EQ(b.point(4).x(), 46.0);
  EXPECT_DOUBLE_EQ(b.point(0).x(), 5.0);
}

TEST(SegmentBuffer, FarFromAllStoredEventsReplacesTheOldest)
{
  ProjectedSegment seg;
  seg.set({0, 0}, {160, 0});  // spacing 20 -> threshold 10 px
  SegmentBuffer b(4);  // spacing 40 px -> threshold 20 px
  for (int i = 0; i < 4; ++i)
    b.insert({10.0 * i, 0}, seg);  // 0, 10, 20, 30: the far end is empty
  EXPECT_EQ(b.insert({150, 0}, seg), 0);  // 120 px from the closest: the oldest (x=0) goes
  EXPECT_EQ(b.insert({90, 0}, seg), 1);   // 60 px from the closest: the oldest (x=10) goes
  EXPECT_EQ(b.insert({140, 0}, seg), 0);  // 10 px from x=150: that one is replaced
  EXPECT_DOUBLE_EQ(b.point(0).x(), 140.0);
}

TEST(SegmentBuffer, StaleEventsOutsideTheAttributionRangeGoFirst)
{
  ProjectedSegment seg;
  seg.set({0, 0}, {80, 0});
  SegmentBuffer b(4);
  b.insert({10, 0}, seg);
  b.insert({30, 3.5}, seg);  // 3.5 px off the current line: stale with a 2 px gate
  b.insert({50, 0}, seg);
  b.insert({70, 0}, seg);
  EXPECT_EQ(b.insert({11, 0}, seg, 2.0, 10.0), 1);
  b.insert({95, 0}, seg);  // 15 px beyond the end (> 10): becomes stale next time
  EXPECT_EQ(b.insert({49, 0}, seg, 2.0, 10.0), 0);  // slot 0 held the (95,0) event
}

TEST(SegmentBuffer, EventsTheLineMovedAwayFromExpire)
{
  // Motion bound 0.5 px: an event stays while its line has moved <= 0.5 px at it since its
  // insertion, whatever its own residual.
  ProjectedSegment seg;
  seg.set({0, 0}, {80, 0});
  SegmentBuffer b(8);
  b.insert({10, 0.3}, seg, 2.0, 10.0, 0.5);  // residual 0.3 px at insertion: kept as long as the line stays
  b.insert({40, -0.2}, seg, 2.0, 10.0, 0.5);
  ProjectedSegment moved = seg;
  moved.set({0, 0.4}, {80, 0.4});  // the line moved 0.4 px along its normal: both stay
  b.expire(moved, 0.5);
  EXPECT_EQ(b.size(), 2);
  // The line rotates about x = 40: 0.75 px of motion at x = 10, none at x = 40.
  moved.set({0, 1.0}, {80, -1.0});
  b.expire(moved, 0.5);
  ASSERT_EQ(b.size(), 1);
  EXPECT_DOUBLE_EQ(b.point(0).x(), 40.0);
  // Inserting with the bound expires too, and the freed slot is reused before any replacement.
  SegmentBuffer c(2);
  c.insert({10, 0}, seg, 2.0, 10.0, 0.5);
  c.insert({70, 0}, seg, 2.0, 10.0, 0.5);
  ProjectedSegment tilted;
  tilted.set({0, 0}, {80, 1.6});  // 1.4 px of motion at x = 70, 0.2 px at x = 10
  const int slot = c.insert({20, 0.4}, tilted, 2.0, 10.0, 0.5);
  EXPECT_EQ(c.size(), 2);
  EXPECT_DOUBLE_EQ(c.point(slot).x(), 20.0);
  EXPECT_TRUE(c.point(0).x() == 10.0 || c.point(1).x() == 10.0);
}
