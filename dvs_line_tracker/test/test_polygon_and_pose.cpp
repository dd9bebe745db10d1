// Polygon search on synthetic segments and exact pose from noise-free corners.
#include <dvs_line_tracker/polygon_search.h>
#include <dvs_line_tracker/pose_initializer.h>
#include "synthetic_events.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace dvs_line_tracker;

namespace
{
const PinholeK kK{115, 115, 63.5, 63.5};

ImageSegment seg(double x0, double y0, double x1, double y1, int n = 50)
{
  return ImageSegment{{x0, y0}, {x1, y1}, n};
}

// The four sides of a projected square, shortened at the corners like Hough segments are.
std::vector<ImageSegment> sidesOf(const std::vector<Eigen::Vector2d>& corners, double shorten_px)
{
  std::vector<ImageSegment> out;
  for (size_t k = 0; k < corners.size(); ++k)
  {
    const Eigen::Vector2d a = corners[k], b = corners[(k + 1) % corners.size()];
    const Eigen::Vector2d d = (b - a).normalized();
    out.push_back({a + shorten_px * d, b - shorten_px * d, 60});
  }
  return out;
}

// An open polygon's two corners in view are `a` and `b` (in either order).
void expectOpenCornersAt(const ImagePolygon& open, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  ASSERT_TRUE(open.open);
  ASSERT_EQ(open.corners.size(), 2u);
  for (const Eigen::Vector2d& e : {a, b})
    EXPECT_LT(std::min((open.corners[0] - e).norm(), (open.corners[1] - e).norm()), 1e-6);
}

std::vector<Eigen::Vector2d> projectCorners(const LineMap& map, const Pose& pose)
{
  std::vector<Eigen::Vector2d> c;
  for (const auto& p : map.polygons[0].corners_world)
    c.push_back(kK.project(pose.toCamera(p)));
  return c;
}
}  // namespace

TEST(PolygonSearch, FindsASquareAmongDistractorsWithCornersAtTheIntersections)
{
  std::vector<ImageSegment> segs = {
      seg(30, 25, 95, 25),    // top (shortened ends)
      seg(100, 30, 100, 95),  // right
      seg(95, 100, 30, 100),  // bottom
      seg(25, 95, 25, 30),    // left
      seg(5, 5, 60, 10),      // distractors
      seg(110, 5, 120, 120),
      seg(40, 60, 80, 62),
  };
  // Shuffle the order and flip some directions: the search must not depend on them.
  std::swap(segs[0], segs[5]);
  std::swap(segs[1].p0, segs[1].p1);
  ImagePolygon poly;
  ASSERT_TRUE(findPolygon(segs, 4, PolygonSearchParams(), poly));
  ASSERT_EQ(poly.corners.size(), 4u);
  std::vector<Eigen::Vector2d> expected = {{25, 25}, {100, 25}, {100, 100}, {25, 100}};
  for (const auto& e : expected)
  {
    double best = 1e9;
    for (const auto& c : poly.corners)
      best = std::min(best, (c - e).norm());
    EXPECT_LT(best, 1e-9) << e.transpose();
  }
  for (int id : poly.segment_ids)
    EXPECT_TRUE(id != 4 && id != 0 && id != 6) << "distractor used: " << id;
}

TEST(PolygonSearch, RejectsOpenChainsBadAnglesAndTinyPolygons)
{
  ImagePolygon poly;
  // Three sides only.
  EXPECT_FALSE(findPolygon({seg(30, 25, 95, 25), seg(100, 30, 100, 95), seg(95, 100, 30, 100)}, 4,
                           PolygonSearchParams(), poly));
  // A rhombus with 30 deg corners: turn angles outside 45..135 deg.
  const double s = 60, a = 30 * M_PI / 180;
  const Eigen::Vector2d p0(20, 60), p1 = p0 + Eigen::Vector2d(s, 0), p3 = p0 + s * Eigen::Vector2d(std::cos(a), -std::sin(a)),
                        p2 = p1 + (p3 - p0);
  EXPECT_FALSE(findPolygon(sidesOf({p0, p1, p2, p3}, 4), 4, PolygonSearchParams(), poly));
  // A 15 px square: sides below the 20 px minimum.
  EXPECT_FALSE(findPolygon(sidesOf({{50, 50}, {65, 50}, {65, 65}, {50, 65}}, 2), 4, [] {
    PolygonSearchParams p;
    return p;
  }(), poly));
  // Segments whose ends are too far apart (gap > a third of the side).
  EXPECT_FALSE(findPolygon(sidesOf({{20, 20}, {80, 20}, {80, 80}, {20, 80}}, 22), 4, PolygonSearchParams(), poly));
  // ... and the same square with small gaps is found.
  EXPECT_TRUE(findPolygon(sidesOf({{20, 20}, {80, 20}, {80, 80}, {20, 80}}, 6), 4, PolygonSearchParams(), poly));
}

TEST(PolygonSearch, WideTurnBoundsFindOnlyWhatTheUsualBoundsCannot)
{
  // A rhombus turning by 30 and 150 deg (a square seen steeply), and beside it an ordinary
  // square: the usual 45..135 deg bounds find only the square; bounds of 25..155 deg that must
  // turn outside 45..135 somewhere find only the rhombus; 25..155 alone finds both.
  const double s = 60, a = 30 * M_PI / 180;
  const Eigen::Vector2d p0(10, 60), p1 = p0 + Eigen::Vector2d(s, 0), p3 = p0 + s * Eigen::Vector2d(std::cos(a), -std::sin(a)),
                        p2 = p1 + (p3 - p0);
  std::vector<ImageSegment> segs = sidesOf({p0, p1, p2, p3}, 4);
  for (const auto& side : sidesOf({{140, 20}, {200, 20}, {200, 80}, {140, 80}}, 4))
    segs.push_back(side);
  const PolygonSearchParams usual;
  PolygonSearchParams wide_only = usual;
  wide_only.min_turn_angle_deg = 25;
  wide_only.max_turn_angle_deg = 155;
  PolygonSearchParams wide = wide_only;
  wide_only.outside_min_turn_angle_deg = usual.min_turn_angle_deg;
  wide_only.outside_max_turn_angle_deg = usual.max_turn_angle_deg;
  auto centreX = [](const ImagePolygon& poly) {
    double x = 0;
    for (const auto& c : poly.corners)
      x += c.x() / poly.corners.size();
    return x;
  };
  const auto found_usual = findPolygons(segs, 4, usual, 8);
  ASSERT_EQ(found_usual.size(), 1u);
  EXPECT_NEAR(centreX(found_usual[0]), 170, 1e-6);
  const auto found_wide_only = findPolygons(segs, 4, wide_only, 8);
  ASSERT_EQ(found_wide_only.size(), 1u);
  EXPECT_NEAR(centreX(found_wide_only[0]), ((p0 + p1 + p2 + p3) / 4).x(), 1e-6);
  EXPECT_EQ(findPolygons(segs, 4, wide, 8).size(), 2u);
}

TEST(PolygonSearch, FindsTrianglesAndPentagonsOfGeneralMaps)
{
  PolygonSearchParams p;
  p.min_turn_angle_deg = 30;
  p.max_turn_angle_deg = 150;
  std::vector<Eigen::Vector2d> tri = {{20, 100}, {100, 100}, {60, 30}};
  ImagePolygon poly;
  ASSERT_TRUE(findPolygon(sidesOf(tri, 5), 3, p, poly));
  EXPECT_EQ(poly.corners.size(), 3u);
  std::vector<Eigen::Vector2d> penta;
  for (int k = 0; k < 5; ++k)
    penta.emplace_back(64 + 45 * std::cos(2 * M_PI * k / 5), 64 + 45 * std::sin(2 * M_PI * k / 5));
  ASSERT_TRUE(findPolygon(sidesOf(penta, 5), 5, p, poly));
  EXPECT_EQ(poly.corners.size(), 5u);
  for (const auto& c : poly.corners)
  {
    double best = 1e9;
    for (const auto& e : penta)
      best = std::min(best, (c - e).norm());
    EXPECT_LT(best, 1e-6);
  }
}

TEST(PolygonSearch, SplitsTheCollinearSidesOfNeighbouringPolygons)
{
  // Two squares side by side whose top and bottom sides are collinear: the Hough detector
  // returns one segment for both tops and one for both bottoms.
  const std::vector<ImageSegment> segs = {
      seg(12, 30, 118, 30),   // both tops
      seg(118, 90, 12, 90),   // both bottoms
      seg(10, 88, 10, 32),    // left square, left side
      seg(55, 33, 55, 87),    // left square, right side
      seg(75, 88, 75, 32),    // right square, left side
      seg(120, 32, 120, 88),  // right square, right side
  };
  // Without splitting, the only square-like polygons use the whole tops and bottoms.
  for (const auto& poly : findPolygons(segs, 4, PolygonSearchParams(), 8))
    for (const auto& c : poly.corners)
      EXPECT_TRUE(std::abs(c.x() - 10) < 1e-6 || std::abs(c.x() - 120) < 1e-6 || std::abs(c.x() - 55) < 1e-6 ||
                  std::abs(c.x() - 75) < 1e-6);
  const std::vector<ImageSegment> split = splitAtJunctions(segs, PolygonSearchParams());
  ASSERT_GT(split.size(), segs.size());
  for (size_t i = 0; i < segs.size(); ++i)  // the detected segments come first, unchanged
    EXPECT_EQ(split[i].p0, segs[i].p0);
  // Both squares are found from the pieces, with exact corners.
  const std::vector<std::vector<Eigen::Vector2d>> squares = {{{10, 30}, {55, 30}, {55, 90}, {10, 90}},
                                                             {{75, 30}, {120, 30}, {120, 90}, {75, 90}}};
  const auto found = findPolygons(split, 4, PolygonSearchParams(), 16);
  for (const auto& square : squares)
  {
    bool have = false;
    for (const auto& poly : found)
    {
      int matched = 0;
      for (const auto& e : square)
        for (const auto& c : poly.corners)
          matched += (c - e).norm() < 1e-6 ? 1 : 0;
      have |= matched == 4;
    }
    EXPECT_TRUE(have) << "square at x " << square[0].x();
  }
  // A segment crossed in its middle by a line that does not end there is not split.
  EXPECT_EQ(splitAtJunctions({seg(10, 50, 110, 50), seg(60, 10, 60, 100)}, PolygonSearchParams()).size(), 2u);

  // Asked for the best two only: the search meets the long tops' and bottoms' polygons first
  // (the outer rectangle), so stopping at two misses the pieces' polygons; collecting more
  // returns the two whose sides meet best of all of them.
  const auto all = findPolygons(split, 4, PolygonSearchParams(), 32);
  ASSERT_GE(all.size(), 4u);
  const auto first_two = findPolygons(split, 4, PolygonSearchParams(), 2);
  ASSERT_EQ(first_two.size(), 2u);
  EXPECT_TRUE(sameCorners(first_two[0], ImagePolygon{{{10, 30}, {120, 30}, {120, 90}, {10, 90}}}));
  EXPECT_GT(first_two[1].gap_px, all[1].gap_px);
  const auto best_two = findPolygons(split, 4, PolygonSearchParams(), 2, 32);
  ASSERT_EQ(best_two.size(), 2u);
  for (size_t i = 0; i < 2; ++i)
  {
    EXPECT_TRUE(sameCorners(best_two[i], all[i]));
    EXPECT_LT(best_two[i].gap_px, first_two[0].gap_px);
  }
}

TEST(PolygonSearch, JoinsTheCollinearPiecesOfASide)
{
  // The segments sweep scene 64's first Hough window gave (a square 77 px wide, rolled 15 deg,
  // hand-held, contrast 3): the right and the top side fire little in their middles, each is
  // detected as two pieces 16 px apart, and no piece reaches both of its side's corners.
  const std::vector<ImageSegment> segs = {
      seg(92.5, 111.8, 17.4, 89.9),  // bottom
      seg(18.3, 91.6, 37.7, 17.9),   // left
      seg(111.4, 35.6, 77.0, 27.0),  // top, right piece
      seg(91.0, 112.3, 99.9, 81.0),  // right, lower piece
      seg(103.7, 64.9, 111.1, 34.3), // right, upper piece
      seg(61.1, 23.5, 36.2, 18.9),   // top, left piece
  };
  EXPECT_TRUE(findPolygons(segs, 4, PolygonSearchParams(), 8).empty());
  const std::vector<ImageSegment> joined = joinCollinearSegments(segs);
  ASSERT_EQ(joined.size(), segs.size() + 2);
  for (size_t i = 0; i < segs.size(); ++i)  // the detected segments come first, unchanged
    EXPECT_EQ(joined[i].p0, segs[i].p0);
  // The joins span their pieces' outer ends and count both pieces' events.
  for (size_t k = segs.size(); k < joined.size(); ++k)
  {
    EXPECT_GT(joined[k].length(), 70.0);
    EXPECT_EQ(joined[k].num_events, 100);
  }
  const auto found = findPolygons(joined, 4, PolygonSearchParams(), 8);
  ASSERT_FALSE(found.empty());
  // Its corners: where the sides' lines meet (within a pixel of the pieces' outer ends).
  const std::vector<Eigen::Vector2d> corners = {{17.9, 90.3}, {37.8, 17.9}, {111.3, 35.4}, {91.7, 112.0}};
  for (const auto& e : corners)
  {
    double nearest = 1e9;
    for (const auto& c : found.front().corners)
      nearest = std::min(nearest, (c - e).norm());
    EXPECT_LT(nearest, 2.0) << e.transpose();
  }

  // Not joined: overlapping pieces, a gap longer than the shorter piece, a parallel line 5 px
  // away, a line turned by 15 deg.
  EXPECT_EQ(joinCollinearSegments({seg(10, 50, 60, 50), seg(50, 50, 100, 50)}).size(), 2u);
  EXPECT_EQ(joinCollinearSegments({seg(10, 50, 60, 50), seg(90, 50, 115, 50)}).size(), 2u);
  EXPECT_EQ(joinCollinearSegments({seg(10, 50, 40, 50), seg(50, 55, 80, 55)}).size(), 2u);
  const double t15 = std::tan(15.0 * M_PI / 180.0);
  EXPECT_EQ(joinCollinearSegments({seg(10, 50, 40, 50), seg(50, 50, 80, 50 + 30 * t15)}).size(), 2u);
  // Joined either way round: a piece before or after the other, either direction.
  for (const auto& pair : {std::vector<ImageSegment>{seg(10, 50, 40, 50), seg(55, 50, 85, 50)},
                           std::vector<ImageSegment>{seg(85, 50, 55, 50), seg(40, 50, 10, 50)}})
  {
    const auto j = joinCollinearSegments(pair);
    ASSERT_EQ(j.size(), 3u);
    EXPECT_NEAR(j[2].length(), 75.0, 1e-9);
    EXPECT_NEAR(std::min(j[2].p0.x(), j[2].p1.x()), 10.0, 1e-9);
  }
}

TEST(PolygonSearch, FindsPolygonsWithOneSideOutOfView)
{
  // A square whose bottom side lies below a 128x128 image: three sides reach or cross the
  // border, the fourth is missing.
  const std::vector<ImageSegment> segs = {
      seg(25, 30, 95, 30),    // top, shortened
      seg(100, 35, 100, 127),  // right, to the border
      seg(20, 127, 20, 35),    // left, from the border
      seg(40, 60, 70, 61),     // a distractor
  };
  ImagePolygon closed;
  EXPECT_FALSE(findPolygon(segs, 4, PolygonSearchParams(), closed));
  const auto open = findOpenPolygons(segs, 4, PolygonSearchParams(), 128, 128, 4.0, 8);
  // The chain through the distractor is a candidate too (the pose fit and the validation on the
  // events judge it); the true one meets best.
  ASSERT_GE(open.size(), 1u);
  expectOpenCornersAt(open[0], {20, 30}, {100, 30});
  EXPECT_GT(open[0].open_first.y(), 120);
  EXPECT_GT(open[0].open_last.y(), 120);
  // The same chain ending inside the image is no partial view.
  const std::vector<ImageSegment> inside = {seg(25, 30, 95, 30), seg(100, 35, 100, 90), seg(20, 90, 20, 35)};
  EXPECT_TRUE(findOpenPolygons(inside, 4, PolygonSearchParams(), 128, 128, 4.0, 8).empty());
  // Triangles have too few sides left to fix a pose.
  EXPECT_TRUE(findOpenPolygons(segs, 3, PolygonSearchParams(), 128, 128, 4.0, 8).empty());
}

TEST(PolygonSearch, CornerFarBeyondTheBorderIsFoundWhenTheSidesReachIt)
{
  // A square tilted 60 deg close to a wide lens (640x480): its lower corner lies 260 px below
  // the image; the two sides that meet there run out of view 210 px apart (the segments of a
  // sweep scene that never started). Without the image, the ends are too far from the corner.
  const std::vector<ImageSegment> segs = {
      seg(60, 66, 349, 135),   // top
      seg(345, 133, 491, 404),  // right
      seg(492, 397, 452, 487),  // lower right, out of view at the bottom
      seg(239, 495, 60, 66),    // left, from below the image
  };
  ImagePolygon poly;
  EXPECT_FALSE(findPolygon(segs, 4, PolygonSearchParams(), poly));
  const auto found = findPolygons(segs, 4, PolygonSearchParams(), 8, 0, ImageView{640, 480, 38});
  ASSERT_EQ(found.size(), 1u);
  const Eigen::Vector2d below(340.5, 738.5);  // the lines' intersection
  EXPECT_TRUE(std::any_of(found[0].corners.begin(), found[0].corners.end(),
                          [&](const Eigen::Vector2d& c) { return (c - below).norm() < 3.0; }));
  // The hidden parts are no gap: only the corners in view count.
  EXPECT_LT(found[0].gap_px, 40.0);
  // Sides that stop inside the image still need their corner near their ends.
  const std::vector<ImageSegment> short_sides = {seg(60, 66, 349, 135), seg(345, 133, 491, 404),
                                                 seg(492, 397, 470, 446), seg(190, 380, 60, 66)};
  EXPECT_TRUE(findPolygons(short_sides, 4, PolygonSearchParams(), 8, 0, ImageView{640, 480, 38}).empty());
}

TEST(PolygonSearch, BridgesAnUndetectedSideBetweenSidesRunningOutOfView)
{
  // A square whose right side lies beyond a 128x128 image and whose left side (parallel to the
  // camera's motion) fired too little to be detected: only the top and bottom sides, each
  // running out of view to the right.
  const std::vector<ImageSegment> segs = {
      seg(32, 30, 127, 30),   // top, from near its corner to the border
      seg(127, 100, 31, 100),  // bottom, from the border
      seg(60, 50, 80, 70),     // a distractor inside the image
  };
  EXPECT_TRUE(findOpenPolygons(segs, 4, PolygonSearchParams(), 128, 128, 4.0, 8).empty());
  const std::vector<ImageSegment> bridged = bridgeBorderSegments(segs, PolygonSearchParams(), 128, 128, 4.0);
  // One bridge: between the inner ends of the two sides that run out of view (the distractor
  // has no end at the border).
  ASSERT_EQ(bridged.size(), segs.size() + 1);
  const auto open = findOpenPolygons(bridged, 4, PolygonSearchParams(), 128, 128, 4.0, 8, static_cast<int>(segs.size()));
  ASSERT_EQ(open.size(), 1u);
  EXPECT_TRUE(open[0].bridged);
  expectOpenCornersAt(open[0], {32, 30}, {31, 100});
  EXPECT_GT(open[0].open_first.x(), 120);
  EXPECT_GT(open[0].open_last.x(), 120);
  // Every polygon has exactly one bridge: with all four sides detected (the left one too) the
  // bridged search finds no second, inferred copy of the chain through the detected left side.
  std::vector<ImageSegment> all = segs;
  all.push_back(seg(31, 98, 32, 32));
  const std::vector<ImageSegment> all_bridged = bridgeBorderSegments(all, PolygonSearchParams(), 128, 128, 4.0);
  for (const ImagePolygon& p :
       findOpenPolygons(all_bridged, 4, PolygonSearchParams(), 128, 128, 4.0, 8, static_cast<int>(all.size())))
  {
    int bridges = 0;
    for (int id : p.segment_ids)
      bridges += id >= static_cast<int>(all.size()) ? 1 : 0;
    EXPECT_EQ(bridges, 1);
  }
  // Segments with both ends inside the image, or crossing it, give no bridges.
  const std::vector<ImageSegment> no_ends = {seg(10, 10, 60, 10), seg(10, 60, 60, 60), seg(0, 90, 127, 90)};
  EXPECT_EQ(bridgeBorderSegments(no_ends, PolygonSearchParams(), 128, 128, 4.0).size(), no_ends.size());
}

TEST(PoseInit, ExactPoseFromAPolygonWithOneSideOutOfView)
{
  const LineMap map = defaultSquareMap();
  const Pose truth = lookAt({0.2, 0.55, 1.0}, {0.1, 0.45, 0}, {0, 1, 0}, 0.15);
  const auto c = projectCorners(map, truth);
  // The corners at the bottom of the image (largest y) are out of view.
  std::vector<int> order = {0, 1, 2, 3};
  std::sort(order.begin(), order.end(), [&](int a, int b) { return c[a].y() < c[b].y(); });
  const int top0 = order[0], top1 = order[1];
  ASSERT_TRUE((top0 + 1) % 4 == top1 || (top1 + 1) % 4 == top0) << "the two top corners share a side";
  const int first = (top0 + 1) % 4 == top1 ? top0 : top1, last = first == top0 ? top1 : top0;
  const int missing_first = (first + 3) % 4, missing_last = (last + 1) % 4;
  ASSERT_GT(c[missing_first].y(), 127.0);
  ASSERT_GT(c[missing_last].y(), 127.0);
  auto atBorder = [](const Eigen::Vector2d& in, const Eigen::Vector2d& out) {
    return Eigen::Vector2d(in + (out - in) * ((127.0 - in.y()) / (out.y() - in.y())));
  };
  ImagePolygon open;
  open.open = true;
  open.corners = {c[first], c[last]};
  open.open_first = atBorder(c[first], c[missing_first]);
  open.open_last = atBorder(c[last], c[missing_last]);
  InitialPose init;
  ASSERT_TRUE(estimateInitialPoseOpen(open, map, kK, PoseInitParams(), init));
  EXPECT_LT(init.reprojection_rms_px, 1e-3);
  const bool exact = positionError(init.pose, truth) < 1e-4 && orientationError(init.pose, truth) < 1e-4;
  bool twin_exact = false;
  for (const Pose& p : init.alternatives)
    twin_exact |= positionError(p, truth) < 1e-4 && orientationError(p, truth) < 1e-4;
  EXPECT_TRUE(exact || twin_exact);
  EXPECT_TRUE(exact) << "the up hint picks the true roll";
  // Sides detected beyond the only consistent missing corners: that side would be in view.
  ImagePolygon too_long = open;
  too_long.open_first = c[missing_first] + 15 * (c[missing_first] - c[first]).normalized();
  too_long.open_last = c[missing_last] + 15 * (c[missing_last] - c[last]).normalized();
  InitialPose none;
  EXPECT_FALSE(estimateInitialPoseOpen(too_long, map, kK, PoseInitParams(), none) &&
               positionError(none.pose, truth) < 0.05);
  // A closed polygon is not an open one.
  ImagePolygon closed = open;
  closed.open = false;
  EXPECT_FALSE(estimateInitialPoseOpen(closed, map, kK, PoseInitParams(), none));
}

TEST(PoseInit, ExactPoseFromNoiseFreeCornersInAnyOrderAndRoll)
{
  const LineMap map = defaultSquareMap();
  for (double roll_deg : {-40.0, -10.0, 0.0, 25.0, 44.0})
  {
    const Pose truth = lookAt({0.3, -0.2, 1.7}, {0.05, 0.02, 0}, {0, 1, 0}, roll_deg * M_PI / 180);
    auto corners = projectCorners(map, truth);
    // The image order starts anywhere and runs either way.
    std::rotate(corners.begin(), corners.begin() + 2, corners.end());
    for (int reversed = 0; reversed < 2; ++reversed)
    {
      if (reversed)
        std::reverse(corners.begin(), corners.end());
      InitialPose init;
      ASSERT_TRUE(estimateInitialPose(corners, map, kK, PoseInitParams(), init)) << roll_deg;
      EXPECT_LT(positionError(init.pose, truth), 1e-6) << roll_deg;
      EXPECT_LT(orientationError(init.pose, truth), 1e-6) << roll_deg;
      EXPECT_LT(init.reprojection_rms_px, 1e-6);
      EXPECT_GT(init.up_score, std::cos(46 * M_PI / 180));
    }
  }
}

TEST(PoseInit, UpHintResolvesTheSquareSymmetry)
{
  // Rolled by 80 deg: the corners are the same as for -10 deg with another assignment; with
  // up = +y the tracker picks the roll within +-45 deg.
  const LineMap map = defaultSquareMap();
  const Pose rolled = lookAt({0, 0, 1.5}, {0, 0, 0}, {0, 1, 0}, 80 * M_PI / 180);
  const Pose expected = lookAt({0, 0, 1.5}, {0, 0, 0}, {0, 1, 0}, -10 * M_PI / 180);
  InitialPose init;
  ASSERT_TRUE(estimateInitialPose(projectCorners(map, rolled), map, kK, PoseInitParams(), init));
  EXPECT_LT(orientationError(init.pose, expected), 1e-6);
  EXPECT_LT(positionError(init.pose, expected), 1e-6);
  // With up = +x the other assignment wins.
  LineMap map_x = map;
  map_x.up_world = Eigen::Vector3d(1, 0, 0);  // image up of the rolled camera
  ASSERT_TRUE(estimateInitialPose(projectCorners(map, rolled), map_x, kK, PoseInitParams(), init));
  EXPECT_LT(orientationError(init.pose, rolled), 1e-6);
}

TEST(PoseInit, UpMarginSaysHowClearlyTheUpHintPicksTheRotation)
{
  // Seen head-on, the square's rotations that fit score cos(roll) and cos(90 deg - roll): the
  // margin between the two most upright is cos(roll) - sin(roll), vanishing at 45 deg.
  const LineMap square = defaultSquareMap();
  for (double roll_deg : {0.0, 20.0, 38.0, 44.0})
  {
    const double roll = roll_deg * M_PI / 180;
    const Pose truth = lookAt({0, 0, 1.5}, {0, 0, 0}, {0, 1, 0}, roll);
    InitialPose init;
    ASSERT_TRUE(estimateInitialPose(projectCorners(square, truth), square, kK, PoseInitParams(), init)) << roll_deg;
    EXPECT_LT(orientationError(init.pose, truth), 1e-6) << roll_deg;
    EXPECT_NEAR(init.up_margin, std::cos(roll) - std::sin(roll), 0.01) << roll_deg;
  }
  // A rectangle fits its corners in one rotation only (and its 180 deg turn, which the up hint
  // rejects with the full margin of 2): no near tie.
  LineMap rect;
  const Eigen::Vector3d c[4] = {{-0.6, -0.3, 0}, {0.6, -0.3, 0}, {0.6, 0.3, 0}, {-0.6, 0.3, 0}};
  for (int i = 0; i < 4; ++i)
    rect.segments.push_back({c[i], c[(i + 1) % 4]});
  finalizeLineMap(rect, "rectangle");
  const Pose tilted = lookAt({0, 0, 1.5}, {0, 0, 0}, {0, 1, 0}, 44 * M_PI / 180);
  InitialPose init;
  ASSERT_TRUE(estimateInitialPose(projectCorners(rect, tilted), rect, kK, PoseInitParams(), init));
  EXPECT_LT(orientationError(init.pose, tilted), 1e-6);
  EXPECT_GT(init.up_margin, 1.0);
}

TEST(PoseInit, TriangleGetsItsOtherP3PSolutionsAsAlternatives)
{
  // A triangle far away (weak perspective): the corners fit the true pose and a pose tilted
  // the other way; the second must be offered for the evidence to decide between them.
  LineMap tri;
  const Eigen::Vector3d c[3] = {{-0.45, -0.39, 0}, {0.45, -0.39, 0}, {0, 0.39, 0}};
  for (int i = 0; i < 3; ++i)
    tri.segments.push_back({c[i], c[(i + 1) % 3]});
  finalizeLineMap(tri, "triangle");
  const Pose truth = lookAt({0.8, 0.5, 4.0}, {0, 0, 0}, {0, 1, 0}, 0.1);
  InitialPose init;
  ASSERT_TRUE(estimateInitialPose(projectCorners(tri, truth), tri, kK, PoseInitParams(), init));
  std::vector<Pose> all{init.pose};
  all.insert(all.end(), init.alternatives.begin(), init.alternatives.end());
  ASSERT_GE(all.size(), 2u);
  const auto hit = std::find_if(all.begin(), all.end(), [&](const Pose& p) {
    return positionError(p, truth) < 1e-4 && orientationError(p, truth) < 1e-4;
  });
  EXPECT_NE(hit, all.end());
  for (const Pose& p : all)
    EXPECT_LT(cornerReprojectionRms(p, kK, projectCorners(tri, truth), tri.polygons[0].corners_world), 1e-3);
}

TEST(PoseInit, ASquaresTurnedAssignmentsFitAsTheSolvedOnesDo)
{
  // The square's corner assignments (quarter turns, reversed orders) are derived from the first
  // one's pose by the square's symmetries, not solved again; a square that is not quite
  // symmetric (one corner 0.1 um off) has every assignment solved. Both must give the same pose,
  // rotations and up margin, on noisy corners seen from a steep angle, at a roll where two
  // rotations nearly tie and at one where they do not.
  const LineMap square = defaultSquareMap();
  LineMap uneven;
  for (auto s : square.segments)
  {
    for (Eigen::Vector3d* p : {&s.p0_world, &s.p1_world})
      if (p->x() > 0 && p->y() > 0)
        *p += Eigen::Vector3d(1e-7, 0, 0);
    uneven.segments.push_back(s);
  }
  finalizeLineMap(uneven, "uneven square");
  const Eigen::Vector2d noise[4] = {{0.3, -0.2}, {-0.25, 0.3}, {0.2, 0.2}, {-0.3, -0.3}};
  for (double roll_deg : {5.0, 40.0})
  {
    const Pose truth = lookAt({0.9, 0.3, 1.1}, {0, 0, 0}, {0, 1, 0}, roll_deg * M_PI / 180);
    auto corners = projectCorners(square, truth);
    for (int i = 0; i < 4; ++i)
      corners[i] += noise[i];
    InitialPose derived, solved;
    ASSERT_TRUE(estimateInitialPose(corners, square, kK, PoseInitParams(), derived)) << roll_deg;
    ASSERT_TRUE(estimateInitialPose(corners, uneven, kK, PoseInitParams(), solved)) << roll_deg;
    EXPECT_LT(positionError(derived.pose, solved.pose), 1e-5) << roll_deg;
    EXPECT_LT(orientationError(derived.pose, solved.pose), 1e-5) << roll_deg;
    EXPECT_NEAR(derived.up_margin, solved.up_margin, 1e-5) << roll_deg;
    EXPECT_NEAR(derived.reprojection_rms_px, solved.reprojection_rms_px, 1e-5) << roll_deg;
    ASSERT_EQ(derived.rotations.size(), solved.rotations.size()) << roll_deg;
    EXPECT_GE(derived.rotations.size(), 1u) << roll_deg;
    for (size_t r = 0; r < derived.rotations.size(); ++r)
      EXPECT_LT(positionError(derived.rotations[r], solved.rotations[r]), 1e-5) << roll_deg;
    EXPECT_LT(positionError(derived.pose, truth), 0.05) << roll_deg;
  }
}

TEST(PoseInit, NoisyCornersGiveACloseRefinedPose)
{
  const LineMap map = defaultSquareMap();
  const Pose truth = lookAt({0.2, 0.1, 1.2}, {0, 0, 0}, {0, 1, 0}, 0.2);
  auto corners = projectCorners(map, truth);
  const Eigen::Vector2d noise[4] = {{0.3, -0.2}, {-0.25, 0.3}, {0.2, 0.2}, {-0.3, -0.3}};
  for (int i = 0; i < 4; ++i)
    corners[i] += noise[i];
  InitialPose init;
  ASSERT_TRUE(estimateInitialPose(corners, map, kK, PoseInitParams(), init));
  EXPECT_LT(init.reprojection_rms_px, 0.4);
  EXPECT_LT(positionError(init.pose, truth), 0.05);
  EXPECT_LT(orientationError(init.pose, truth), 3 * M_PI / 180);
}

TEST(PoseInit, CornersThatFitNoPoseAreRejected)
{
  const LineMap map = defaultSquareMap();
  // A strongly non-projective quadrilateral (a "kite" with one corner pulled far out).
  std::vector<Eigen::Vector2d> corners = {{30, 30}, {90, 30}, {120, 120}, {30, 90}};
  PoseInitParams p;
  p.max_reprojection_rms_px = 0.5;
  InitialPose init;
  EXPECT_FALSE(estimateInitialPose(corners, map, kK, p, init));
  // Wrong number of corners for the map's polygons.
  EXPECT_FALSE(estimateInitialPose({{30, 30}, {90, 30}, {60, 90}}, map, kK, PoseInitParams(), init));
}
