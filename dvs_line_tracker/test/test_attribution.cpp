// Event attribution regions (thesis Fig. 4.5) and buffer replacement (Fig. 4.6).
#include <dvs_line_tracker/segment_attribution.h>
#include <dvs_line_tracker/tracker_params.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

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

TEST(Attribution, TheTrackerLeavesTheNeighbouringSidesCornerAlone)
{
  // la fires in a band as it moves along its normal (a camera rising past the square); an event
  // of that band 2.5 px above la lies 0.5 px from lb's line and 2.5 px beyond lb's end. The
  // thesis's 10 px beyond an end gave it to lb, which hardly fires while it moves along itself:
  // such events biased lb's direction (the pitch of the 2 m flip's rise). The tracker's default
  // reaches 2 px beyond an end, as beside a segment.
  const auto segs = corner();
  int out[2];
  ASSERT_EQ(attributeEvent({79.5, 17.5}, segs.data(), 2, AttributionParams(), out), 1);
  EXPECT_EQ(out[0], 1);
  const AttributionParams tracker = LineTrackerParams().attribution;
  EXPECT_DOUBLE_EQ(tracker.max_orthogonal_px, 2.0);
  EXPECT_DOUBLE_EQ(tracker.max_parallel_px, 2.0);
  EXPECT_EQ(attributeEvent({79.5, 17.5}, segs.data(), 2, tracker, out), 0);
  // 1.5 px beyond lb's far end, away from any corner: still lb's.
  ASSERT_EQ(attributeEvent({80.5, 81.5}, segs.data(), 2, tracker, out), 1);
  EXPECT_EQ(out[0], 1);
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

namespace
{
/// The buffer rule written out plainly (one pass over every stored event per insertion, as the
/// rule in segment_attribution.h reads): the reference the fast buffer must agree with.
struct PlainBuffer
{
  explicit PlainBuffer(int capacity) : capacity(capacity) {}
  int capacity;
  std::vector<Eigen::Vector2d> points;
  std::vector<double> offsets;
  std::vector<uint64_t> stamps;
  uint64_t clock = 0;

  void removeAt(size_t i)
  {
    points[i] = points.back();
    offsets[i] = offsets.back();
    stamps[i] = stamps.back();
    points.pop_back();
    offsets.pop_back();
    stamps.pop_back();
  }
  void expire(const ProjectedSegment& seg, double max_motion)
  {
    for (size_t i = 0; i < points.size();)
      if (std::abs(seg.normal.dot(points[i] - seg.a) - offsets[i]) > max_motion)
        removeAt(i);
      else
        ++i;
  }
  int insert(const Eigen::Vector2d& p, const ProjectedSegment& seg, double max_orth, double max_par, double max_motion)
  {
    ++clock;
    if (max_motion < 1e299)
      expire(seg, max_motion);
    int slot = static_cast<int>(points.size());
    if (slot < capacity)
    {
      points.push_back(p);
      offsets.push_back(0);
      stamps.push_back(0);
    }
    else
    {
      int stale = -1, closest = 0, oldest = 0;
      double worst = 0, best = 1e300;
      const double s_new = seg.dir.dot(p - seg.a);
      for (int i = 0; i < capacity; ++i)
      {
        const double o = seg.normal.dot(points[i] - seg.a), s = seg.dir.dot(points[i] - seg.a);
        const double excess = std::max(std::abs(o) - max_orth, std::max(-s, s - seg.length) - max_par);
        if (excess > worst)
          worst = excess, stale = i;
        if (std::abs(s - s_new) < best)
          best = std::abs(s - s_new), closest = i;
        if (stamps[i] < stamps[oldest])
          oldest = i;
      }
      slot = stale >= 0 ? stale : (best < 0.5 * seg.length / capacity ? closest : oldest);
    }
    points[slot] = p;
    offsets[slot] = seg.normal.dot(p - seg.a);
    stamps[slot] = clock;
    return slot;
  }
};
}  // namespace

TEST(SegmentBuffer, SkippingTheExaminationOfEveryEventChoosesWhatTheRuleChooses)
{
  // A line that drifts, turns and jumps, events around it (some stale, some repeated at the
  // same place), expiries between insertions: the buffer's slot choice and contents must be
  // those of the plain rule at every step, and its fast path (no event examined but the
  // replacement search) must have been taken most of the time for this to mean anything.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g(0, 1);
  int checked = 0;
  uint64_t examined = 0;
  for (int trial = 0; trial < 40; ++trial)
  {
    const int capacity = 2 + trial % 12 * 4;
    const double max_orth = 1.0 + u(rng) * 2, max_par = 5 + u(rng) * 10;
    const double max_motion = trial % 4 == 0 ? 1e300 : 0.2 + u(rng) * 0.8;
    SegmentBuffer fast(capacity);
    PlainBuffer plain(capacity);
    double angle = u(rng) * 6.3, offset = 0, along0 = 0, length = 40 + u(rng) * 60;
    for (int step = 0; step < 3000; ++step)
    {
      // The line moves a little most of the time and jumps now and then.
      const bool jump = u(rng) < 0.003;
      angle += (jump ? 0.2 : 0.002) * g(rng);
      offset += (jump ? 3.0 : 0.02) * g(rng);
      along0 += 0.05 * g(rng);
      length = std::max(10.0, length + 0.05 * g(rng));
      const Eigen::Vector2d dir(std::cos(angle), std::sin(angle)), normal(-dir.y(), dir.x());
      const Eigen::Vector2d a = Eigen::Vector2d(64, 64) + offset * normal + along0 * dir;
      ProjectedSegment seg;
      seg.set(a, a + length * dir);
      if (u(rng) < 0.02)
      {
        fast.expire(seg, max_motion < 1e299 ? max_motion : 0.5);
        plain.expire(seg, max_motion < 1e299 ? max_motion : 0.5);
      }
      // Events on pixel-like positions near the line (repeats happen), a few far off.
      const double t = std::round((u(rng) * 1.2 - 0.1) * length * 4) / 4;
      const double o = u(rng) < 0.05 ? 3 * max_orth * g(rng) : std::round(0.7 * g(rng) * 4) / 4;
      const Eigen::Vector2d p = a + t * dir + o * normal;
      const int s_fast = fast.insert(p, seg, max_orth, max_par, max_motion);
      const int s_plain = plain.insert(p, seg, max_orth, max_par, max_motion);
      ASSERT_EQ(s_fast, s_plain) << "trial " << trial << " step " << step;
      ASSERT_EQ(fast.size(), static_cast<int>(plain.points.size()));
      for (int i = 0; i < fast.size(); ++i)
      {
        ASSERT_EQ(fast.point(i), plain.points[i]) << "trial " << trial << " step " << step << " slot " << i;
        ASSERT_EQ(fast.stamp(i), plain.stamps[i]);
      }
      ++checked;
    }
    examined += fast.examinations();
  }
  EXPECT_EQ(checked, 40 * 3000);
  EXPECT_LT(examined, static_cast<uint64_t>(checked / 2));
}
