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
};

struct ImagePolygon
{
  /// corners[k] is where side k-1 meets side k; side k runs from corners[k] to corners[k+1].
  std::vector<Eigen::Vector2d> corners;
  std::vector<int> segment_ids;  ///< indices into the searched segments, one per side
  double gap_px = 0;             ///< summed distances of the sides' ends from their corners
  double perimeter() const;
  /// Signed area (shoelace, image coordinates, y down).
  double signedArea() const;
};

/// Intersection of the infinite lines through two segments; false when (nearly) parallel.
bool intersectLines(const ImageSegment& a, const ImageSegment& b, Eigen::Vector2d& point);

/// The polygon with `num_sides` sides whose sides meet best (smallest gap_px among the first 8
/// found, longer segments first). Returns false when there is none.
bool findPolygon(const std::vector<ImageSegment>& segments, int num_sides, const PolygonSearchParams& params,
                 ImagePolygon& polygon);

/// Up to `max_polygons` distinct polygons (different sets of segments; the search tries longer
/// segments first), sorted by gap_px (sides that meet best first), so that a caller can try the
/// next when one fails.
std::vector<ImagePolygon> findPolygons(const std::vector<ImageSegment>& segments, int num_sides,
                                       const PolygonSearchParams& params, int max_polygons);
}  // namespace dvs_line_tracker
