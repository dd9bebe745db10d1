// PointGrid: its queries visit every point of the region once (a superset of it, never a point
// twice), whatever the points and the query.
#include <dvs_line_tracker/point_grid.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>

using namespace dvs_line_tracker;

namespace
{
double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

// How often each point was visited, by its coordinates (the test points are distinct).
using Visits = std::map<std::pair<double, double>, int>;
}  // namespace

TEST(PointGrid, VisitsEveryPointNearASegmentOnce)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(-40, 680), y(-30, 500);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 3000; ++i)
    points.emplace_back(x(rng), y(rng));
  PointGrid grid(8.0);
  grid.reset(points);
  EXPECT_EQ(grid.size(), points.size());
  size_t visited_total = 0;
  for (int q = 0; q < 200; ++q)
  {
    // Segments of every length and direction, some reaching far outside the points, one a point.
    Eigen::Vector2d a(x(rng), y(rng)), b(x(rng), y(rng));
    if (q % 17 == 0)
      b = a;
    if (q % 23 == 0)
      b = a + 1e9 * (b - a).normalized();
    const double radius = 0.5 + 6.0 * (q % 5);
    Visits visits;
    grid.forEachNearSegment(a, b, radius, [&](const Eigen::Vector2d& p) { ++visits[{p.x(), p.y()}]; });
    visited_total += visits.size();
    for (const auto& v : visits)
      EXPECT_EQ(v.second, 1);
    for (const auto& p : points)
      if (distanceToSegment(p, a, b) <= radius)
        EXPECT_EQ(visits.count({p.x(), p.y()}), 1u) << "query " << q;
  }
  // The point of the grid: a query visits a small part of the points, not all of them.
  EXPECT_LT(visited_total, 200u * points.size() / 4);
}

TEST(PointGrid, VisitsEveryPointInABoxOnceAndSkipsNonFinitePoints)
{
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 40; ++j)
      points.emplace_back(i * 2.5, j * 3.0);
  points.emplace_back(std::numeric_limits<double>::quiet_NaN(), 1.0);
  points.emplace_back(1.0, std::numeric_limits<double>::infinity());
  PointGrid grid(8.0);
  grid.reset(points);
  EXPECT_EQ(grid.size(), 2000u);
  Visits visits;
  grid.forEachInBox({10, 20}, {30.5, 45}, [&](const Eigen::Vector2d& p) { ++visits[{p.x(), p.y()}]; });
  int inside = 0;
  for (const auto& p : points)
    if (p.allFinite() && p.x() >= 10 && p.x() <= 30.5 && p.y() >= 20 && p.y() <= 45)
    {
      ++inside;
      EXPECT_EQ(visits.count({p.x(), p.y()}), 1u);
    }
  EXPECT_EQ(inside, 9 * 9);
  for (const auto& v : visits)
    EXPECT_EQ(v.second, 1);
  // Boxes beyond the points, inverted or not finite: nothing; an empty grid: nothing.
  int n = 0;
  grid.forEachInBox({500, 500}, {600, 600}, [&](const Eigen::Vector2d&) { ++n; });
  grid.forEachInBox({30, 30}, {10, 10}, [&](const Eigen::Vector2d&) { ++n; });
  grid.forEachNearSegment({std::nan(""), 0}, {1, 1}, 5, [&](const Eigen::Vector2d&) { ++n; });
  EXPECT_EQ(n, 0);
  // A box around everything, reaching far beyond it: every finite point once.
  Visits all;
  grid.forEachInBox({-1e12, -1e12}, {1e12, 1e12}, [&](const Eigen::Vector2d& p) { ++all[{p.x(), p.y()}]; });
  EXPECT_EQ(all.size(), 2000u);
  grid.reset({});
  grid.forEachInBox({-1e12, -1e12}, {1e12, 1e12}, [&](const Eigen::Vector2d&) { ++n; });
  EXPECT_EQ(n, 0);
  EXPECT_THROW(PointGrid(0.0), std::invalid_argument);
}

TEST(PointGrid, StrayPointsFarAwayKeepTheGridSmallAndTheQueriesComplete)
{
  // One point 1e9 px away would make 8 px cells number 1e16: the cells grow instead.
  std::vector<Eigen::Vector2d> points = {{0, 0}, {5, 5}, {1e9, 1e9}, {100, 3}};
  PointGrid grid(8.0);
  grid.reset(points);
  Visits visits;
  grid.forEachNearSegment({0, 0}, {100, 0}, 6.0, [&](const Eigen::Vector2d& p) { ++visits[{p.x(), p.y()}]; });
  EXPECT_EQ(visits.count({0, 0}), 1u);
  EXPECT_EQ(visits.count({5, 5}), 1u);
  EXPECT_EQ(visits.count({100, 3}), 1u);
}
