// Hough line candidates and segment splitting with known answers.
#include <dvs_line_tracker/hough_line_detector.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
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

TEST(SegmentSplit, BucketsSplitWhereTheSortedPointsDo)
{
  // The split without a sort against the rule written out: sort the points near the line along
  // it, split where neighbours are more than max_gap_px apart (gaps of exactly max_gap_px
  // included, which do not split), keep pieces long and dense enough. Random clusters along a
  // tilted line with gaps around the limit, off-line clutter, and a gap parameter so small that
  // buckets would outnumber the points (the sorted fallback).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 300; ++trial)
  {
    HoughParams p;
    const bool tiny_gap = trial % 10 == 9;
    p.max_gap_px = tiny_gap ? 1e-9 : 5.0 + 20.0 * u(rng);
    p.min_segment_events = tiny_gap ? 1 : 1 + trial % 12;
    p.min_segment_length_px = tiny_gap ? 0.0 : 10.0 * u(rng);
    ImageLine line;
    line.theta = 3.0 * u(rng);
    line.r = 40.0 * u(rng);
    const Eigen::Vector2d n = line.normal(), dir(-n.y(), n.x());
    std::vector<Eigen::Vector2d> pts;
    double s = -100.0 * u(rng);
    for (int cluster = 0; cluster < 6; ++cluster)
    {
      const int count = static_cast<int>(40 * u(rng));
      for (int i = 0; i < count; ++i)
      {
        s += 3.0 * u(rng);
        pts.push_back((line.r + 3.0 * (u(rng) - 0.5)) * n + s * dir);
      }
      const double gap = u(rng) < 0.3 ? p.max_gap_px : p.max_gap_px * (0.5 + u(rng));
      s += gap;
      if (u(rng) < 0.5)
        pts.push_back(line.r * n + s * dir);  // a point exactly one gap on
    }
    std::shuffle(pts.begin(), pts.end(), rng);

    std::vector<std::pair<double, int>> along;
    for (size_t i = 0; i < pts.size(); ++i)
      if (std::abs(pts[i].dot(n) - line.r) <= p.attribution_distance_px)
        along.emplace_back(pts[i].dot(dir), static_cast<int>(i));
    std::sort(along.begin(), along.end());
    std::vector<std::pair<int, double>> expected;  // events, length along the line
    size_t begin = 0;
    for (size_t i = 1; i <= along.size(); ++i)
    {
      if (i < along.size() && along[i].first - along[i - 1].first <= p.max_gap_px)
        continue;
      const int count = static_cast<int>(i - begin);
      const double length = along[i - 1].first - along[begin].first;
      if (count >= p.min_segment_events && length >= p.min_segment_length_px)
        expected.emplace_back(count, length);
      begin = i;
    }

    const auto segs = splitIntoSegments(pts, line, p);
    // A refitted piece can come out shorter than min_segment_length_px and is then dropped.
    ASSERT_LE(segs.size(), expected.size()) << "trial " << trial;
    size_t k = 0;
    for (const auto& [count, length] : expected)
    {
      if (k < segs.size() && segs[k].num_events == count)
      {
        EXPECT_NEAR(segs[k].length(), length, 2.0) << "trial " << trial;
        ++k;
      }
      else
        EXPECT_LT(length, p.min_segment_length_px + 3.0) << "trial " << trial << ": a piece went missing";
    }
    EXPECT_EQ(k, segs.size()) << "trial " << trial;
  }
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
// The four thick sides of a square (2 half_width + 1 px), their events interleaved as an edge
// sweep makes them; a pixel `w` px off a side's line fires max(1, peak_events - |w|) times.
void addThickSquare(HoughLineDetector& h, double x0, double y0, double side, int half_width = 1, int peak_events = 1)
{
  for (int step = 0; step <= static_cast<int>(side); ++step)
    for (int w = -half_width; w <= half_width; ++w)
    {
      const double s = step;
      const Eigen::Vector2d pts[4] = {{x0 + s, y0 + w}, {x0 + side + w, y0 + s}, {x0 + side - s, y0 + side + w},
                                      {x0 + w, y0 + side - s}};
      for (const auto& p : pts)
        for (int repeat = 0; repeat < std::max(1, peak_events - std::abs(w)); ++repeat)
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

// The same segments, bit for bit, in the same order.
bool sameSegments(const std::vector<ImageSegment>& a, const std::vector<ImageSegment>& b)
{
  if (a.size() != b.size())
    return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].p0 != b[i].p0 || a[i].p1 != b[i].p1 || a[i].num_events != b[i].num_events)
      return false;
  return true;
}
}  // namespace

TEST(Hough, ASecondDetectionOnTheSameWindowIsTheOneAFreshDetectorMakes)
{
  // The initialiser runs the full Hough right after the progressive one on the same window, and
  // the detector reuses what the first pass found per bin. Whatever ran before, each detection
  // must be the one a detector fed the same events makes from scratch; an event voted in between
  // makes the window new.
  HoughParams p;
  p.neighbour_filter = false;
  HoughLineDetector reused(128, 128, p);
  addThickSquare(reused, 30, 30, 60);
  const auto progressive = reused.detectSegments(true);
  const auto peaks = reused.detectSegments(HoughLineDetector::Pass::kRadiusPeaks);
  const auto full = reused.detectSegments(false);
  const auto full_again = reused.detectSegments(false);
  {
    HoughLineDetector fresh(128, 128, p);
    addThickSquare(fresh, 30, 30, 60);
    EXPECT_TRUE(sameSegments(full, fresh.detectSegments(false)));
    EXPECT_TRUE(sameSegments(full_again, full));
    HoughLineDetector fresh_peaks(128, 128, p);
    addThickSquare(fresh_peaks, 30, 30, 60);
    EXPECT_TRUE(sameSegments(peaks, fresh_peaks.detectSegments(HoughLineDetector::Pass::kRadiusPeaks)));
    HoughLineDetector fresh_progressive(128, 128, p);
    addThickSquare(fresh_progressive, 30, 30, 60);
    EXPECT_TRUE(sameSegments(progressive, fresh_progressive.detectSegments(true)));
  }
  // A copy detects on its own points (the original it was copied from may be gone by then:
  // without its own scratch, the copy read the freed points).
  {
    std::unique_ptr<HoughLineDetector> copy;
    {
      auto original = std::make_unique<HoughLineDetector>(128, 128, p);
      addThickSquare(*original, 30, 30, 60);
      original->detectSegments(true);
      copy = std::make_unique<HoughLineDetector>(*original);
      original->reset();
      addThickSquare(*original, 10, 50, 40);
      original->detectSegments(false);
    }
    EXPECT_TRUE(sameSegments(copy->detectSegments(false), full));
  }
  // A new side voted in: the next detection sees it.
  int64_t t = 0;
  addSegmentEvents(reused, {10, 110}, {110, 110}, t);
  const auto after = reused.detectSegments(true);
  HoughLineDetector fresh(128, 128, p);
  addThickSquare(fresh, 30, 30, 60);
  t = 0;
  addSegmentEvents(fresh, {10, 110}, {110, 110}, t);
  EXPECT_TRUE(sameSegments(after, fresh.detectSegments(true)));
  EXPECT_FALSE(sameSegments(after, progressive));
}

TEST(Hough, AWrappedWindowVotesAndDetectsAsAFreshDetectorFedItsEvents)
{
  // Each window slot keeps its event's curve bins from its vote, for the event's removal (the
  // window slides, events expire by age) and for the progressive pass's removal of explained
  // votes, whose points start anywhere in the ring. A detector fed only the window's events, in
  // order, from an empty ring must hold the same votes and find the same segments.
  HoughParams p;
  p.neighbour_filter = false;
  p.window_events = 700;
  p.max_event_age_s = 0.5;
  // Points beyond the sensor (ideal pixels of a barrel-distorted lens) leave some curves outside
  // the accumulator at some angles.
  const double ideal_radius = 120;
  HoughLineDetector slid(128, 128, p, ideal_radius);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-40, 168);
  auto noise = [&](int n, int64_t& t, int64_t dt) {
    for (int i = 0; i < n; ++i, t += dt)
      slid.addEvent(static_cast<float>(u(rng)), static_cast<float>(u(rng)), -1, -1, t);
  };
  int64_t t = 0;
  noise(900, t, 1000000);  // 0-0.9 s: the ring wraps, and events older than 0.5 s expire
  for (const auto& [a, b] : std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>{
           {{30, 30}, {90, 30}}, {{90, 30}, {90, 90}}, {{90, 90}, {30, 90}}, {{30, 90}, {30, 30}}})
    addSegmentEvents(slid, a, b, t);  // a square: the full ring drops the oldest
  t = 1200000000;
  noise(30, t, 1000000);  // 1.2-1.23 s: the noise before 0.73 s expires by age
  const std::vector<Eigen::Vector2d> window = slid.windowPoints();
  ASSERT_GT(window.size(), 400u);
  ASSERT_LT(window.size(), 700u);  // some expired by age
  HoughLineDetector fresh(128, 128, p, ideal_radius);
  int64_t tf = 0;
  for (const auto& q : window)
    fresh.addEvent(static_cast<float>(q.x()), static_cast<float>(q.y()), -1, -1, tf++);
  int differing = 0, voted = 0;
  for (int k = 0; k < slid.numAngleBins(); ++k)
    for (int rb = 0; rb < slid.numRadiusBins(); ++rb)
    {
      differing += slid.votes(k, rb) != fresh.votes(k, rb);
      voted += slid.votes(k, rb);
    }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(voted, 0);
  const auto progressive = slid.detectSegments(true);
  EXPECT_FALSE(progressive.empty());
  EXPECT_TRUE(sameSegments(progressive, fresh.detectSegments(true)));
  // The progressive pass took the votes of the same events out.
  int explained = 0;
  differing = 0;
  for (int k = 0; k < slid.numAngleBins(); ++k)
    for (int rb = 0; rb < slid.numRadiusBins(); ++rb)
    {
      differing += slid.unexplainedVotes(k, rb) != fresh.unexplainedVotes(k, rb);
      explained += slid.votes(k, rb) - slid.unexplainedVotes(k, rb);
    }
  EXPECT_EQ(differing, 0);
  EXPECT_GT(explained, 0);
  EXPECT_TRUE(sameSegments(slid.detectSegments(HoughLineDetector::Pass::kRadiusPeaks),
                   fresh.detectSegments(HoughLineDetector::Pass::kRadiusPeaks)));
}

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

TEST(Hough, RadiusPeaksFindEverySideOfABandFromFewerLines)
{
  // An edge that moved while the window filled is a band several radius bins wide, densest
  // where the edge spent longest. Every bin across the band fits a line of its own and adds
  // pieces beside the side; the radius peaks find each side from fewer lines.
  HoughParams p;
  p.neighbour_filter = false;
  p.window_events = 8000;
  p.max_candidates = 1000;
  p.max_segments = 1000;
  HoughLineDetector h(128, 128, p);
  addThickSquare(h, 30, 30, 60, 4, 5);  // a 9 px band, 5 events per pixel on the side's line
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> sides = {
      {{30, 30}, {90, 30}}, {{90, 30}, {90, 90}}, {{90, 90}, {30, 90}}, {{30, 90}, {30, 30}}};
  const auto every = h.detectSegments(HoughLineDetector::Pass::kEveryBin);
  const auto peaks = h.detectSegments(HoughLineDetector::Pass::kRadiusPeaks);
  // The band's corners overlap the neighbouring sides' bands: the ends lie up to half the
  // band's width beyond the corners.
  EXPECT_EQ(matchedSides(every, sides, 5.0), 4);
  EXPECT_EQ(matchedSides(peaks, sides, 5.0), 4);
  EXPECT_LT(peaks.size(), every.size() * 3 / 4);
  // Some candidate bins of the band are shoulders, not peaks, and every peak has as many votes
  // as its radius neighbours.
  int shoulders = 0;
  for (const auto& [k, rb] : h.candidateBins())
  {
    const bool peak = h.radiusPeak(k, rb);
    shoulders += !peak;
    if (peak)
    {
      if (rb > 0)
        EXPECT_GE(h.votes(k, rb), h.votes(k, rb - 1));
      if (rb + 1 < h.numRadiusBins())
        EXPECT_GE(h.votes(k, rb), h.votes(k, rb + 1));
    }
  }
  EXPECT_GT(shoulders, 0);
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
