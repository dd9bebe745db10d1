// Line map: the default square, YAML round trip, and clear errors for bad maps.
#include <dvs_line_tracker/line_map.h>

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
