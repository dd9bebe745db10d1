// LinePointIndex: its queries return a superset of the points a scan of all of them selects,
// in the points' order, for any angle (folded into [0, pi), near pi, negative) and range.
#include <dvs_line_tracker/line_point_index.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace dvs_line_tracker;

namespace
{
const Eigen::Vector2d kCentre(63.5, 63.5);
constexpr double kRMax = 95.0, kBucket = 2.5;

bool ascending(const std::vector<int>& v)
{
  return std::adjacent_find(v.begin(), v.end(), [](int a, int b) { return a >= b; }) == v.end();
}
}  // namespace

TEST(LinePointIndex, NearLineQueriesHoldEveryPointAScanFinds)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-20, 150), angle(-7, 7), offset(-60, 60);
  std::vector<Eigen::Vector2d> points(1500);
  for (auto& p : points)
    p = {coord(rng), coord(rng)};
  LinePointIndex index(24, kRMax, kBucket, kCentre);
  index.reset(points);
  EXPECT_EQ(index.anglesBuilt(), 0);
  std::vector<int> got;
  size_t total = 0;
  for (int q = 0; q < 500; ++q)
  {
    // Every tenth query at an angle exactly between two accumulator angles or next to pi.
    double theta = angle(rng);
    if (q % 10 == 0)
      theta = (q / 10 % 2 == 0) ? M_PI - 1e-9 : (q / 10) * M_PI / 24 + M_PI / 48;
    const Eigen::Vector2d n(std::cos(theta), std::sin(theta));
    const double r = n.dot(kCentre) + offset(rng), d = 2.0;
    index.nearLine(theta, r, d, got);
    EXPECT_TRUE(ascending(got));
    for (size_t i = 0; i < points.size(); ++i)
      if (std::abs(points[i].dot(n) - r) <= d)
        ASSERT_TRUE(std::binary_search(got.begin(), got.end(), static_cast<int>(i)))
            << "query " << q << " theta " << theta << " misses point " << i;
    total += got.size();
  }
  // A superset, but a small one: a 4 px band among points spread over 170 px.
  EXPECT_LT(total, 500u * points.size() / 5);
  EXPECT_GT(index.anglesBuilt(), 0);
  EXPECT_LE(index.anglesBuilt(), 24);
}

TEST(LinePointIndex, AngleRangeQueriesHoldEveryPointWhoseCurvePassesTheRange)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coord(0, 127), radius(-80, 80);
  std::vector<Eigen::Vector2d> points(800);
  for (auto& p : points)
    p = {coord(rng), coord(rng)};
  LinePointIndex index(24, kRMax, kBucket, kCentre);
  index.reset(points);
  const double half = 0.5 * M_PI / 24;
  std::vector<int> got;
  for (int k = 0; k < 24; ++k)
    for (int q = 0; q < 10; ++q)
    {
      const double theta = k * M_PI / 24, lo = radius(rng), hi = lo + kBucket;
      index.candidates(theta, lo, hi, half, got);
      EXPECT_TRUE(ascending(got));
      for (size_t i = 0; i < points.size(); ++i)
        for (const double phi : {theta - half, theta, theta + half})
        {
          const double r = (points[i] - kCentre).dot(Eigen::Vector2d(std::cos(phi), std::sin(phi)));
          if (r >= lo && r <= hi)
            ASSERT_TRUE(std::binary_search(got.begin(), got.end(), static_cast<int>(i)));
        }
    }
}

TEST(LinePointIndex, PointsBeyondTheRadiusRangeAndDegenerateQueries)
{
  // Points far outside [-r_max, r_max] go to the end buckets and are still found.
  const std::vector<Eigen::Vector2d> points = {{500, 63.5}, {-400, 63.5}, {63.5, 63.5}};
  LinePointIndex index(24, kRMax, kBucket, kCentre);
  index.reset(points);
  std::vector<int> got;
  index.nearLine(0.0, 500.0, 1.0, got);
  EXPECT_EQ(got, std::vector<int>({0}));
  index.nearLine(M_PI, 400.0, 1.0, got);  // x = -400 as the line at pi
  EXPECT_EQ(got, std::vector<int>({1}));
  index.nearLine(-3 * M_PI, 400.0, 1.0, got);  // the same line, turned
  EXPECT_EQ(got, std::vector<int>({1}));
  // A huge angle (beyond folding by a rounded 2 pi): the line through the centre still holds
  // that point.
  const double huge = 1e300;
  index.nearLine(huge, kCentre.dot(Eigen::Vector2d(std::cos(huge), std::sin(huge))), 1.0, got);
  EXPECT_TRUE(std::find(got.begin(), got.end(), 2) != got.end());
  // A query with nothing to narrow it by (not finite, or a wide angle range) returns every point.
  index.nearLine(std::nan(""), 0.0, 1.0, got);
  EXPECT_EQ(got.size(), 3u);
  index.candidates(0.0, -1.0, 1.0, M_PI, got);
  EXPECT_EQ(got.size(), 3u);
  // An empty set answers nothing; bad construction is refused.
  const std::vector<Eigen::Vector2d> none;
  index.reset(none);
  index.nearLine(0.0, 0.0, 1.0, got);
  EXPECT_TRUE(got.empty());
  EXPECT_THROW(LinePointIndex(0, kRMax, kBucket, kCentre), std::invalid_argument);
  EXPECT_THROW(LinePointIndex(24, kRMax, 0.0, kCentre), std::invalid_argument);
}

TEST(LinePointIndex, KnownBucketsFromARingGiveTheQueriesOfComputedOnes)
{
  // A Hough window's ring of curve bins (24 per slot, written from slot 1300 on and wrapped at
  // 1500), with -1 where a point's radius left the grid: the queries must return exactly what
  // an index that computes every bucket returns. A wrong slot or angle of the ring fails this.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coord(-60, 190), angle(-7, 7), offset(-70, 70), width(0, 0.2);
  const int angles = 24, capacity = 1500, start = 1300;
  std::vector<Eigen::Vector2d> points(1400);
  for (auto& p : points)
    p = {coord(rng), coord(rng)};
  std::vector<int32_t> ring(static_cast<size_t>(capacity) * angles, -7);
  const int buckets = static_cast<int>(std::ceil(2 * kRMax / kBucket));
  int outside = 0;
  for (size_t i = 0; i < points.size(); ++i)
  {
    const int slot = static_cast<int>((start + i) % capacity);
    for (int k = 0; k < angles; ++k)
    {
      const double th = k * M_PI / angles;
      const double r = (points[i].x() - kCentre.x()) * std::cos(th) + (points[i].y() - kCentre.y()) * std::sin(th);
      const int rb = static_cast<int>((r + kRMax) / kBucket);
      ring[static_cast<size_t>(slot) * angles + k] = rb >= 0 && rb < buckets ? rb : -1;
      outside += rb >= 0 && rb < buckets ? 0 : 1;
    }
  }
  ASSERT_GT(outside, 100);  // the points reach beyond the grid at some angles
  LinePointIndex computed(angles, kRMax, kBucket, kCentre), known(angles, kRMax, kBucket, kCentre);
  computed.reset(points);
  known.reset(points, {ring.data(), angles, start, capacity});
  std::vector<int> a, b;
  for (int q = 0; q < 600; ++q)
  {
    const double theta = angle(rng), half = q % 2 ? width(rng) : 0.0;
    const double r = offset(rng);
    computed.candidates(theta, r - 1.25, r + 1.25, half, a);
    known.candidates(theta, r - 1.25, r + 1.25, half, b);
    ASSERT_EQ(a, b) << "query " << q;
  }
  EXPECT_EQ(known.anglesBuilt(), angles);
  // Buckets that cannot cover the points are refused.
  EXPECT_THROW(known.reset(points, {ring.data(), angles, start, 1000}), std::invalid_argument);
  EXPECT_THROW(known.reset(points, {ring.data(), 12, start, capacity}), std::invalid_argument);
}
