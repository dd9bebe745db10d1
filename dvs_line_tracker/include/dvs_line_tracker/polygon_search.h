#pragma once
// Polygon search over detected image segments (thesis 4.2.1 "Finding the Square"), generalised
// to n sides: segments are tried longest first, each from both ends; a chain grows through
// segments which turn the same way by 45-135 deg and whose line meets the current one at a
// corner beyond the middle of both, with each segment's end within a gap of the corner (a
// third of the two segments' summed lengths: segments of slowly moving edges often stop short
// of their corners); a chain of n segments whose last side meets the first is a polygon. Its
// corners are the intersections of neighbouring sides, and polygons with a side shorter than
// the minimum are rejected.
#include <dvs_line_tracker/hough_line_detector.h>

#include <Eigen/Core>
#include <vector>

namespace dvs_line_tracker
{
struct PolygonSearchParams
{
  double min_turn_angle_deg = 45.0;       ///< angle between neighbouring sides' directions, lower bound
  double max_turn_angle_deg = 135.0;      ///< upper bound
  double corner_proximity_ratio = 1.0 / 3.0;  ///< a side end to its corner (the lines' intersection), at most this fraction of the two sides' summed lengths
  double min_side_px = 20.0;              ///< shortest accepted side (corner to corner)
  int max_steps = 20000;                  ///< search budget (chain extensions)
  /// Only polygons with at least one turn outside [outside_min, outside_max] deg (the default
  /// 0 / 180: every polygon). A search with wider turn bounds then finds only the polygons a
  /// search with the bounds [outside_min, outside_max] could not.
  double outside_min_turn_angle_deg = 0.0;
  double outside_max_turn_angle_deg = 180.0;
};

struct ImagePolygon
{
  /// corners[k] is where side k-1 meets side k; side k runs from corners[k] to corners[k+1].
  std::vector<Eigen::Vector2d> corners;
  std::vector<int> segment_ids;  ///< indices into the searched segments, one per side
  double gap_px = 0;             ///< summed distances of the sides' ends from their corners
  /// An open polygon (findOpenPolygons): one side out of view. `corners` then holds the n-2
  /// corners in view (corners[k] where side k meets side k+1 of the n-1 sides found); the
  /// first side runs from `open_first` to corners.front(), the last from corners.back() to
  /// `open_last` (both ends at the image border).
  bool open = false;
  /// An open polygon with one side in view inferred, not detected (a bridge between the inner
  /// ends of two sides running out of view; bridgeBorderSegments).
  bool bridged = false;
  Eigen::Vector2d open_first = Eigen::Vector2d::Zero(), open_last = Eigen::Vector2d::Zero();
  double perimeter() const;
  /// Signed area (shoelace, image coordinates, y down).
  double signedArea() const;
};

/// The image the segments were detected in, for polygons cut by its border: a side's end within
/// `border_px` of the border [0, width - 1] x [0, height - 1] may be followed by a hidden part,
/// so a corner beyond the border is not required near it. width <= 0: no image known (every
/// corner must lie near its sides' ends).
struct ImageView
{
  double width = 0, height = 0, border_px = 0;
  bool known() const { return width > 0 && height > 0; }
};

/// The same polygon: as many corners, each within 0.5 px of one of the other's (in any order),
/// both open or both closed.
bool sameCorners(const ImagePolygon& a, const ImagePolygon& b);

/// Intersection of the infinite lines through two segments; false when (nearly) parallel.
bool intersectLines(const ImageSegment& a, const ImageSegment& b, Eigen::Vector2d& point);

/// Polygons of `num_sides` (>= 4) sides with one side out of view: chains of num_sides - 1
/// sides meeting as in findPolygon whose two outer ends reach the border of the image
/// [0, width - 1] x [0, height - 1] (within `border_px`, or beyond it). Up to `max_polygons`,
/// sorted by gap_px. With `first_bridge` >= 0 the segments from that index on are bridges
/// (bridgeBorderSegments) and each polygon has exactly one of them as an inner side.
std::vector<ImagePolygon> findOpenPolygons(const std::vector<ImageSegment>& segments, int num_sides,
                                           const PolygonSearchParams& params, double width, double height,
                                           double border_px, int max_polygons, int first_bridge = -1);

/// `p` within `border_px` of the border of the image [0, width - 1] x [0, height - 1], or beyond.
bool atImageBorder(const Eigen::Vector2d& p, double width, double height, double border_px);

/// `segments` followed by bridges: a segment between the inner ends of every pair of segments
/// (each at least min_side_px long) that run out of view with one end (atImageBorder) and whose
/// inner ends are at least min_side_px apart. A polygon side parallel to the camera's motion
/// hardly fires and is not detected; when its neighbours run out of view, their inner ends are
/// its corners.
std::vector<ImageSegment> bridgeBorderSegments(const std::vector<ImageSegment>& segments,
                                               const PolygonSearchParams& params, double width, double height,
                                               double border_px);

/// `segments` followed by the pieces of every segment in whose interior the line of another
/// segment ends (a T or L junction): neighbouring polygons with collinear sides (two squares
/// side by side, a triangle on a square's base line) are detected as one long segment whose
/// corners lie inside it; its pieces between junctions are the polygons' sides. Junctions are
/// where the other segment (turning by min..max_turn_angle_deg) has an end within the corner
/// gap, at least min_side_px from both ends of the split segment. At most
/// 2 * segments.size() pieces are added (longest segments first).
std::vector<ImageSegment> splitAtJunctions(const std::vector<ImageSegment>& segments,
                                           const PolygonSearchParams& params);

/// `segments` followed by the joins of collinear pairs: a side that fires little along part of
/// its length (its middle moving along itself, a low-contrast edge) is detected as two pieces on
/// one line, split at a gap longer than the Hough's, and neither piece reaches both corners. Two
/// segments join when their inner ends lie within 2 px of the line between their outer ends (the
/// pieces' own directions, from 20-40 px, differ by up to 4 deg on one side: at most 10 deg is
/// asked of them), they do not overlap and the gap between them is at most
/// the shorter one's length (so that two thirds of the joined side were seen).
/// The join spans both pieces' outer ends and counts both pieces' events. At most
/// segments.size() joins are added (shortest gaps first).
std::vector<ImageSegment> joinCollinearSegments(const std::vector<ImageSegment>& segments);

/// The polygon with `num_sides` sides whose sides meet best (smallest gap_px among the first 8
/// found, longer segments first). Returns false when there is none.
bool findPolygon(const std::vector<ImageSegment>& segments, int num_sides, const PolygonSearchParams& params,
                 ImagePolygon& polygon);

/// Up to `max_polygons` distinct polygons (different sets of segments; the search tries longer
/// segments first), sorted by gap_px (sides that meet best first), so that a caller can try the
/// next when one fails. With `search_polygons` > max_polygons, that many are collected and the
/// best max_polygons of them returned (the first found use the longest segments, which may
/// join neighbouring polygons' collinear sides). With a known `view`, a corner beyond the image
/// border may lie any distance (up to the image size beyond the border) from the ends of its
/// sides that reach the border (a corner out of view at the start).
std::vector<ImagePolygon> findPolygons(const std::vector<ImageSegment>& segments, int num_sides,
                                       const PolygonSearchParams& params, int max_polygons, int search_polygons = 0,
                                       const ImageView& view = ImageView());
}  // namespace dvs_line_tracker
