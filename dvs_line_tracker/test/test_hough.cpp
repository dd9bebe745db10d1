// Hough line candidates and segment splitting with known answers.
#include <dvs_line_tracker/hough_line_detector.h>

#include <gtest/gtest.h>

#include <random>

using namespace dvs_line_tracker;

namespace
{
// Events along a segment, one per pixel step, with time stamps close together.
void addSegmentEvents(HoughLineDetector& h, const Eigen::Vector2d& a, const Eigen::Vector2d& b, int64_t& t)
{
  const int n = static_cast<int>((b - a).norm());
  for (int i = 0; i <= n; ++i)
  {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / n);
    const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
    h.addEvent(static_cast<float>(x), static_cast<float>(y), x, y, t);
    t += 1000;
  }
}
}  // namespace

TEST(Hough, BinsHaveTheThesisResolution)
{
  HoughLineDetector h(128, 128);
  EXPECT_EQ(h.numAngleBins(), 24);  // 180 / 7.5
  EXPECT_GE(h.numRadiusBins(), 73); // thesis: 24 x 73 bins
  EXPECT_LE(h.numRadiusBins(), 80);
}

TEST(Hough, OneHorizontalLineIsACandidateAtTheRightBin)
{
  HoughParams p;
  p.neighbour_filter = false;
  HoughLineDetector h(128, 128, p);
  int64_t t = 0;
  addSegmentEvents(h, {20, 40}, {100, 40}, t);  // 81 events on y = 40
  const auto bins = h.candidateBins();
  ASSERT_FALSE(bins.empty());
  const ImageLine best = h.binLine(bins[0].first, bins[0].second);
  // Normal close to +y (theta ~ 90 deg), r ~ 40.
  EXPECT_NEAR(std::abs(std::sin(best.theta)), 1.0, 0.01);
  EXPECT_NEAR(best.r, 40.0, 2.5);
  EXPECT_GE(h.votes(bins[0].first, bins[0].second), 25);
  const auto segs = h.detectSegments();
  ASSERT_EQ(segs.size(), 1u);
  EXPECT_NEAR(segs[0].length(), 80.0, 1.0);
  EXPECT_NEAR(segs[0].p0.y(), 40.0, 0.1);
  EXPECT_NEAR(segs[0].p1.y(), 40.0, 0.1);
  EXPECT_NEAR(std::min(segs[0].p0.x(), segs[0].p1.x()), 20.0, 0.5);
  EXPECT_NEAR(std::max(segs[0].p0.x(), segs[0].p1.x()), 100.0, 0.5);
}

TEST(Hough, FewEventsAreNotACandidate)
{
  HoughParams p;
  p.neighbour_filter = false;
  HoughLineDetector h(128, 128, p);
  int64_t t = 0;
  addSegmentEvents(h, {20, 40}, {40, 40}, t);  // 21 events < threshold 25
  EXPECT_TRUE(h.candidateBins().empty());
  EXPECT_TRUE(h.detectSegments().empty());
}

TEST(Hough, SlidingWindowForgetsOldVotes)
{
  HoughParams p;
  p.neighbour_filter = false;
  p.window_events = 100;
  HoughLineDetector h(128, 128, p);
  int64_t t = 0;
  addSegmentEvents(h, {10, 20}, {110, 20}, t);  // 101 events: the first is forgotten
  addSegmentEvents(h, {10, 90}, {110, 90}, t);  // pushes the first line out entirely
  EXPECT_EQ(h.numWindowEvents(), 100);
  const auto segs = h.detectSegments();
  ASSERT_EQ(segs.size(), 1u);
  EXPECT_NEAR(segs[0].p0.y(), 90.0, 0.5);
}

TEST(Hough, NeighbourFilterDropsIsolatedNoise)
{
  HoughLineDetector h(128, 128);  // filter on by default: 2 of 8 neighbours among the last 500 events
  int voted = 0;
  for (int i = 0; i < 200; ++i)
  {
    // Isolated pixels: no neighbour ever fires.
    const int x = 2 + 4 * (i % 30), y = 2 + 4 * (i / 30);
    voted += h.addEvent(x, y, x, y, static_cast<int64_t>(i) * 1000) ? 1 : 0;
  }
  EXPECT_EQ(voted, 0);
  // A 2-px wide edge swept along x: from the second column on, every pixel has two recent
  // neighbours in the previous column.
  for (int x = 10; x < 60; ++x)
    for (int y = 30; y < 32; ++y)
      voted += h.addEvent(x, y, x, y, 0) ? 1 : 0;
  EXPECT_EQ(voted, 2 * 49);
  // Neighbours that fired more than 500 events ago do not count.
  for (int i = 0; i < 600; ++i)
    h.addEvent(120, 120, 120, 120, 0);
  EXPECT_FALSE(h.addEvent(60, 31, 60, 31, 0));
}

TEST(SegmentSplit, GapsLongerThan15PxSplitAndShortPiecesAreDropped)
{
  HoughParams p;  // gap 15, min length 20, min events 25
  std::vector<Eigen::Vector2d> pts;
  for (int x = 0; x <= 40; ++x)
    pts.emplace_back(x, 50.0);  // 41 events, 40 px
  for (int x = 50; x <= 90; ++x)
    pts.emplace_back(x, 50.0);  // gap 10 px: same segment
  for (int x = 110; x <= 125; ++x)
    pts.emplace_back(x, 50.0);  // gap 20 px: new segment, only 15 px / 16 events: dropped
  for (int x = 0; x < 128; x += 3)
    pts.emplace_back(x, 60.0);  // 10 px away: not attributed
  ImageLine line;
  line.theta = M_PI / 2;
  line.r = 50;
  const auto segs = splitIntoSegments(pts, line, p);
  ASSERT_EQ(segs.size(), 1u);
  EXPECT_EQ(segs[0].num_events, 82);
  EXPECT_NEAR(segs[0].length(), 90.0, 1e-6);

  // Sparse: 30 px long but only 11 events -> dropped.
  std::vector<Eigen::Vector2d> sparse;
  for (int x = 0; x <= 30; x += 3)
    sparse.emplace_back(x, 50.0);
  EXPECT_TRUE(splitIntoSegments(sparse, line, p).empty());
}

TEST(SegmentSplit, FitLineRecoversATiltedLine)
{
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < 50; ++i)
    pts.emplace_back(10 + i, 20 + 0.5 * i);
  const ImageLine l = fitLine(pts);
  for (const auto& q : pts)
    EXPECT_NEAR(l.distance(q), 0.0, 1e-9);
}
