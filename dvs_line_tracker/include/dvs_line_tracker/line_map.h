#pragma once
// The map the tracker follows: straight 3D edges in the world frame (metres), plus the closed
// polygons they form (used by the initialisation) and an "up" hint that resolves the
// symmetry of regular polygons (thesis 4.2.1: roll about the optical axis within +-45 deg).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <stdexcept>
#include <string>
#include <vector>

namespace dvs_line_tracker
{
/// Thrown for unreadable, malformed or unusable map files; the message names the problem.
class LineMapError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

struct MapSegment
{
  Eigen::Vector3d p0_world;
  Eigen::Vector3d p1_world;
};

/// A closed chain of map segments. `segment_ids[k]` runs from `corners_world[k]` to
/// `corners_world[(k+1) % n]`.
struct MapPolygon
{
  std::vector<int> segment_ids;
  std::vector<Eigen::Vector3d> corners_world;
  bool planar = true;  ///< all corners within 1 mm of their best-fit plane
};

/// A polygon's normal by Newell's method (length twice its area when planar), pointing to its
/// front: the side from which its corners run anticlockwise.
Eigen::Vector3d frontNormal(const MapPolygon& poly);
/// The mean of a polygon's corners.
Eigen::Vector3d cornerCentroid(const MapPolygon& poly);

struct LineMap
{
  std::string frame_id = "world";
  Eigen::Vector3d up_world = Eigen::Vector3d(0, 1, 0);
  std::vector<MapSegment> segments;
  std::vector<MapPolygon> polygons;  ///< filled by finalizeLineMap()
};

/// The thesis's target: a 0.9 m x 0.9 m square in the world plane z = 0, centred on the
/// origin, the wall normal +z pointing towards the camera, up = +y.
LineMap defaultSquareMap(double side_m = 0.9);

/// Load the YAML map of ../shared/reference/formats.md (frame_id, up, segments). Throws
/// LineMapError naming the file and the problem (missing/empty segments, a segment that is not
/// two 3-vectors, non-finite numbers, degenerate segments shorter than 1 mm, a zero up vector,
/// a map without any closed polygon).
LineMap loadLineMap(const std::string& path);
/// Same from YAML text (`name` is used in messages).
LineMap parseLineMap(const std::string& yaml_text, const std::string& name);

/// Validate the segments and find the closed polygons (endpoints shared within 1 mm). Throws
/// LineMapError on an empty map, a degenerate segment, or no closed polygon.
void finalizeLineMap(LineMap& map, const std::string& name = "map");

/// The map's symmetries: the rigid motions S other than the identity that map its segments onto
/// its segments (endpoints within `tolerance_m`, either direction) and keep its front side: for
/// a planar map, rotations about the plane's normal through its centroid (the square's 90, 180
/// and 270 deg; two squares side by side: 180 deg). A camera at T_world_camera and one at
/// S * T_world_camera see the same image. Non-planar maps: none (not searched).
std::vector<Eigen::Isometry3d> lineMapSymmetries(const LineMap& map, double tolerance_m = 1e-3);

/// YAML text of a map (the formats.md layout).
std::string lineMapToYaml(const LineMap& map);
}  // namespace dvs_line_tracker
