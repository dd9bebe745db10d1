// Line map: the default square, YAML round trip, and clear errors for bad maps.
#include <dvs_line_tracker/line_map.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <gtest/gtest.h>

using namespace dvs_line_tracker;

TEST(LineMap, DefaultSquareIsOneClosedPlanarPolygon)
{
  const LineMap map = defaultSquareMap();
  ASSERT_EQ(map.segments.size(), 4u);
  ASSERT_EQ(map.polygons.size(), 1u);
  EXPECT_EQ(map.polygons[0].corners_world.size(), 4u);
  EXPECT_TRUE(map.polygons[0].planar);
  for (const auto& s : map.segments)
    EXPECT_NEAR((s.p1_world - s.p0_world).norm(), 0.9, 1e-12);
  // Its front faces the camera (+z), the normal twice the area long.
  const Eigen::Vector3d n = frontNormal(map.polygons[0]);
  EXPECT_NEAR(n.x(), 0, 1e-12);
  EXPECT_NEAR(n.y(), 0, 1e-12);
  EXPECT_NEAR(n.z(), 2 * 0.81, 1e-12);
}

TEST(LineMap, YamlRoundTrip)
{
  const LineMap map = defaultSquareMap(0.5);
  const LineMap back = parseLineMap(lineMapToYaml(map), "round trip");
  ASSERT_EQ(back.segments.size(), 4u);
  for (size_t i = 0; i < 4; ++i)
  {
    EXPECT_TRUE(back.segments[i].p0_world.isApprox(map.segments[i].p0_world));
    EXPECT_TRUE(back.segments[i].p1_world.isApprox(map.segments[i].p1_world));
  }
  EXPECT_TRUE(back.up_world.isApprox(map.up_world));
  EXPECT_EQ(back.polygons.size(), 1u);
}

TEST(LineMap, SegmentsInAnyDirectionAndOrderFormAPolygon)
{
  const std::string yaml = R"(
frame_id: world
up: [0, 0, 2]
segments:
  - [[0, 0, 0], [1, 0, 0]]
  - [[0, 1, 0], [1, 1, 0]]
  - [[0, 0, 0], [0, 1, 0]]
  - [[1, 1, 0], [1, 0, 0]]
  - [[3, 3, 3], [4, 4, 4]]
)";
  const LineMap map = parseLineMap(yaml, "test");
  EXPECT_EQ(map.segments.size(), 5u);
  ASSERT_EQ(map.polygons.size(), 1u);
  EXPECT_EQ(map.polygons[0].segment_ids.size(), 4u);
  EXPECT_NEAR(map.up_world.norm(), 1.0, 1e-12);  // normalised
}

TEST(LineMap, BadMapsGiveClearErrors)
{
  auto expectError = [](const std::string& yaml, const std::string& fragment) {
    try
    {
      parseLineMap(yaml, "m.yaml");
      FAIL() << "no error for: " << yaml;
    }
    catch (const LineMapError& e)
    {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("m.yaml"), std::string::npos) << e.what();
    }
  };
  expectError("segments: []", "missing or empty");
  expectError("frame_id: world", "missing or empty");
  expectError("segments:\n  - [[0,0,0],[0,0,0]]", "degenerate");
  expectError("segments:\n  - [[0,0,0],[1,0]]", "3 numbers");
  expectError("segments:\n  - [[0,0,0],[1,0,x]]", "numbers");
  expectError("segments:\n  - [[0,0,0],[1,0,0]]\n  - [[2,0,0],[3,0,0]]", "no closed polygon");
  expectError("up: [0,0,0]\nsegments:\n  - [[0,0,0],[1,0,0]]\n  - [[1,0,0],[0,1,0]]\n  - [[0,1,0],[0,0,0]]", "up");
  expectError("segments: [[[0,0,0],[1,0,0]]", "not valid YAML");
  // A square with one corner 5 cm out of its plane (a typo): refused, naming the deviation.
  expectError("segments:\n  - [[0,0,0],[1,0,0]]\n  - [[1,0,0],[1,1,0.05]]\n  - [[1,1,0.05],[0,1,0]]\n"
              "  - [[0,1,0],[0,0,0]]",
              "is not planar (a corner lies 12.5");
  EXPECT_THROW(loadLineMap("/nonexistent/map.yaml"), LineMapError);
}

namespace
{
LineMap mapOf(const std::vector<std::vector<Eigen::Vector3d>>& polygons)
{
  LineMap map;
  for (const auto& c : polygons)
    for (size_t i = 0; i < c.size(); ++i)
      map.segments.push_back({c[i], c[(i + 1) % c.size()]});
  finalizeLineMap(map, "test");
  return map;
}

/// Every segment of `map` moved by `s` lands on a segment of `map`.
bool mapsOntoItself(const LineMap& map, const Eigen::Isometry3d& s)
{
  for (const auto& a : map.segments)
  {
    bool hit = false;
    for (const auto& b : map.segments)
      hit |= ((s * a.p0_world - b.p0_world).norm() < 1e-9 && (s * a.p1_world - b.p1_world).norm() < 1e-9) ||
             ((s * a.p0_world - b.p1_world).norm() < 1e-9 && (s * a.p1_world - b.p0_world).norm() < 1e-9);
    if (!hit)
      return false;
  }
  return true;
}

double turnDeg(const Eigen::Isometry3d& s) { return Eigen::AngleAxisd(s.linear()).angle() * 180 / M_PI; }
}  // namespace

TEST(LineMap, SymmetriesAreTheRotationsThatMapTheMapOntoItself)
{
  // The square: 90, 180 and 270 deg about its normal through its centre.
  const auto square = lineMapSymmetries(defaultSquareMap());
  ASSERT_EQ(square.size(), 3u);
  std::vector<double> angles;
  for (const auto& s : square)
  {
    EXPECT_TRUE(mapsOntoItself(defaultSquareMap(), s));
    EXPECT_NEAR(std::abs(s.linear().col(2).dot(Eigen::Vector3d::UnitZ())), 1.0, 1e-12);  // about the normal
    angles.push_back(turnDeg(s));
  }
  std::sort(angles.begin(), angles.end());
  EXPECT_NEAR(angles[0], 90, 1e-6);
  EXPECT_NEAR(angles[1], 90, 1e-6);  // +90 and -90 (= 270)
  EXPECT_NEAR(angles[2], 180, 1e-6);
  // Two squares side by side: only the half turn about the point between them.
  const LineMap pair = mapOf({{{-1.035, -0.45, 0}, {-0.135, -0.45, 0}, {-0.135, 0.45, 0}, {-1.035, 0.45, 0}},
                              {{0.135, -0.45, 0}, {1.035, -0.45, 0}, {1.035, 0.45, 0}, {0.135, 0.45, 0}}});
  const auto two = lineMapSymmetries(pair);
  ASSERT_EQ(two.size(), 1u);
  EXPECT_NEAR(turnDeg(two[0]), 180, 1e-6);
  EXPECT_TRUE(mapsOntoItself(pair, two[0]));
  EXPECT_NEAR((two[0] * Eigen::Vector3d(-0.585, 0, 0) - Eigen::Vector3d(0.585, 0, 0)).norm(), 0, 1e-9);
  // A square and a triangle, and a rectangle off the origin turned by 30 deg: no map symmetry
  // but the rectangle's half turn about its own centre.
  EXPECT_TRUE(lineMapSymmetries(mapOf({{{-1.035, -0.45, 0}, {-0.135, -0.45, 0}, {-0.135, 0.45, 0}, {-1.035, 0.45, 0}},
                                        {{0.135, -0.39, 0}, {1.035, -0.39, 0}, {0.585, 0.39, 0}}}))
                  .empty());
  const Eigen::Isometry3d place = Eigen::Translation3d(2, 1, 3) * Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 2, 3).normalized());
  const LineMap rect = mapOf({{place * Eigen::Vector3d(-0.6, -0.3, 0), place * Eigen::Vector3d(0.6, -0.3, 0),
                               place * Eigen::Vector3d(0.6, 0.3, 0), place * Eigen::Vector3d(-0.6, 0.3, 0)}});
  const auto half = lineMapSymmetries(rect);
  ASSERT_EQ(half.size(), 1u);
  EXPECT_NEAR(turnDeg(half[0]), 180, 1e-6);
  EXPECT_TRUE(mapsOntoItself(rect, half[0]));
  // A map over two planes (a square and a square 0.3 m in front of it, offset sideways) has no
  // symmetry (planar maps only are searched).
  EXPECT_TRUE(lineMapSymmetries(mapOf({{{-0.45, -0.45, 0}, {0.45, -0.45, 0}, {0.45, 0.45, 0}, {-0.45, 0.45, 0}},
                                        {{1, -0.45, 0.3}, {1.9, -0.45, 0.3}, {1.9, 0.45, 0.3}, {1, 0.45, 0.3}}}))
                  .empty());
}
