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


TEST(Hough, EventsOlderThanTheAgeLimitStopVotingAndAreNoEvidence)
{
  // A slow scene's count window would otherwise still hold what the camera saw seconds before
  // (screen_sim's alignment grid, whose rows of dots made a false square 7 s later).
  HoughParams p;
  p.neighbour_filter = false;
  p.evidence_events = 3000;
  EXPECT_DOUBLE_EQ(p.max_event_age_s, 3.0);  // the default
  p.max_event_age_s = 1.0;
  HoughLineDetector h(128, 128, p);
  int64_t t = 0;
  addSegmentEvents(h, {10, 20}, {110, 20}, t);  // 101 events around t = 0
  t = 600000000;                                // 0.6 s
  addSegmentEvents(h, {10, 90}, {110, 90}, t);  // 101 events around 0.6 s
  EXPECT_EQ(h.numWindowEvents(), 202);
  EXPECT_EQ(h.detectSegments().size(), 2u);
  // An event at 1.3 s: the first line (older than 0.3 s) is forgotten, the second is not.
  h.addEvent(64, 64, 64, 64, 1300000000);
  EXPECT_EQ(h.numWindowEvents(), 102);
  const auto window = h.windowPoints();
  ASSERT_EQ(window.size(), 102u);
  EXPECT_NEAR(window.front().y(), 90.0, 1e-9);  // oldest first
  EXPECT_NEAR(window.back().x(), 64.0, 1e-9);
  EXPECT_EQ(h.evidencePoints().size(), 102u);
  // The times of the window's events: the latest, the oldest of the latest 2, and of all.
  EXPECT_EQ(h.timeOfLatest(1), 1300000000);
  EXPECT_EQ(h.timeOfLatest(2), 600000000 + 100 * 1000);
  EXPECT_EQ(h.timeOfLatest(100000), 600000000);
  const auto segs = h.detectSegments();
  ASSERT_EQ(segs.size(), 1u);
  EXPECT_NEAR(segs[0].p0.y(), 90.0, 0.5);
  // A new line fills the freed window slots in order, and a pause empties the window.
  t = 1400000000;
  addSegmentEvents(h, {20, 10}, {20, 110}, t);
  EXPECT_EQ(h.numWindowEvents(), 203);
  EXPECT_NEAR(h.windowPoints().front().y(), 90.0, 1e-9);
  h.addEvent(64, 64, 64, 64, 5000000000);
  EXPECT_EQ(h.numWindowEvents(), 1);
  EXPECT_TRUE(h.detectSegments().empty());
  h.reset();
  EXPECT_EQ(h.timeOfLatest(1), 0);  // empty

  // 0: no age limit, only the count window.
  p.max_event_age_s = 0;
  HoughLineDetector unlimited(128, 128, p);
  t = 0;
  addSegmentEvents(unlimited, {10, 20}, {110, 20}, t);
  unlimited.addEvent(64, 64, 64, 64, 100000000000);
  EXPECT_EQ(unlimited.numWindowEvents(), 102);
  p.max_event_age_s = -1;
  EXPECT_THROW(HoughLineDetector(128, 128, p), std::invalid_argument);
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

namespace
{
// The four thick (3 px) sides of a square, their events interleaved as an edge sweep makes them.
void addThickSquare(HoughLineDetector& h, double x0, double y0, double side)
{
  for (int step = 0; step <= static_cast<int>(side); ++step)
    for (int w = -1; w <= 1; ++w)
    {
      const double s = step;
      const Eigen::Vector2d pts[4] = {{x0 + s, y0 + w}, {x0 + side + w, y0 + s}, {x0 + side - s, y0 + side + w},
                                      {x0 + w, y0 + side - s}};
      for (const auto& p : pts)
      {
        const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
        h.addEvent(static_cast<float>(x), static_cast<float>(y), x, y, 0);
      }
    }
}

// How many of `expected` (p0, p1 in any order) have a segment within `tol` px at both ends.
int matchedSides(const std::vector<ImageSegment>& segs, const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& expected,
                 double tol)
{
  int matched = 0;
  for (const auto& [a, b] : expected)
    for (const auto& s : segs)
      if (((s.p0 - a).norm() < tol && (s.p1 - b).norm() < tol) || ((s.p0 - b).norm() < tol && (s.p1 - a).norm() < tol))
      {
        ++matched;
        break;
      }
  return matched;
}
}  // namespace

TEST(Hough, ProgressiveVoteRemovalFindsTheSameSidesOfAThickSquare)
{
  // Thick edges put many bins over the threshold along each side: with the found segments'
  // votes removed the other bins of a side are no candidates; the four sides come out as with
  // every bin examined, without the pieces of each side that the other bins add.
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> sides = {
      {{30, 30}, {90, 30}}, {{90, 30}, {90, 90}}, {{90, 90}, {30, 90}}, {{30, 90}, {30, 30}}};
  for (const bool progressive : {false, true})
  {
    HoughParams p;
    p.neighbour_filter = false;
    p.remove_found_votes = progressive;
    HoughLineDetector h(128, 128, p);
    addThickSquare(h, 30, 30, 60);
    const auto segs = h.detectSegments();
    EXPECT_EQ(matchedSides(segs, sides, 2.5), 4) << "progressive " << progressive;
    if (progressive)
      EXPECT_EQ(segs.size(), 4u);  // without: pieces of the thick sides beside them too
    else
      EXPECT_GT(segs.size(), 4u);
  }
}

TEST(Hough, ProgressiveVoteRemovalKeepsASideWhoseCornerEventsAnotherSideTook)
{
  // An L of two short sides just over the threshold: the first side found explains the corner's
  // events; the second side still has enough votes of its own.
  HoughParams p;
  p.neighbour_filter = false;
  p.remove_found_votes = true;
  HoughLineDetector h(128, 128, p);
  int64_t t = 0;
  addSegmentEvents(h, {40, 40}, {40, 80}, t);  // 41 events
  addSegmentEvents(h, {40, 40}, {72, 40}, t);  // 33 events, one of them the shared corner
  const auto segs = h.detectSegments();
  EXPECT_EQ(matchedSides(segs, {{{40, 40}, {40, 80}}, {{40, 40}, {72, 40}}}, 1.5), 2);
}
