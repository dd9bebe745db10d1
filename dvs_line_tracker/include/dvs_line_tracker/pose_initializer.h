#pragma once
// Initial pose from the corners of a detected image polygon (thesis 4.2.1 "Initial Pose
// Estimation"): every cyclic assignment of image corners to the map polygon's corners, in both
// directions, is solved with planar PnP (IPPE; SQPnP for non-planar polygons); assignments
// that reproject badly or put the polygon behind the camera are dropped; among the rest the
// one whose projected map "up" points most nearly up in the image wins (this resolves the
// symmetry of a square: roll about the optical axis within +-45 deg); the winner is refined by
// minimising the corners' reprojection error with Ceres.
#include <dvs_line_tracker/pose_types.h>
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/polygon_search.h>

#include <Eigen/Core>
#include <limits>
#include <vector>

namespace dvs_line_tracker
{
/// Ideal (undistorted) pinhole intrinsics used by the tracker: the undistorted image of the
/// shared camera model has the same K.
struct PinholeK
{
  double fx = 115, fy = 115, cx = 63.5, cy = 63.5;
  /// Project a camera-frame point to an ideal pixel (no check of z).
  Eigen::Vector2d project(const Eigen::Vector3d& p_cam) const
  {
    return {fx * p_cam.x() / p_cam.z() + cx, fy * p_cam.y() / p_cam.z() + cy};
  }
};

struct PoseInitParams
{
  double max_reprojection_rms_px = 2.0;  ///< assignments reprojecting worse are rejected
  bool refine = true;                    ///< Ceres refinement of the reprojection error
};

struct InitialPose
{
  Pose pose;
  double reprojection_rms_px = 0;  ///< after refinement
  double up_score = 0;             ///< cosine between projected map up and image up (-y)
  /// up_score minus that of the best other assignment of the corners to the same polygon that
  /// also fits (a symmetric polygon's rotations: the square's at 90 deg); infinite when none.
  double up_margin = std::numeric_limits<double>::infinity();
  int polygon_index = -1;          ///< the map polygon used
  std::vector<int> corner_assignment;  ///< image corner k <-> map polygon corner corner_assignment[k]
  /// The other solution of planar PnP for the same corners (IPPE's twin; for a triangle the
  /// other P3P solutions), when it also reprojects within the
  /// limit and sees the polygon from the front: in a weak-perspective view (narrow lens, far
  /// away) a polygon tilted the other way projects to nearly the same corners. The caller tells
  /// the two apart with more evidence (the events along every map edge).
  std::vector<Pose> alternatives;
  /// The other assignments of the corners to the same polygon that also fit and see it from the
  /// front (a symmetric polygon's other rotations: the square's at 90, 180, 270 deg), most
  /// upright first. The map's up picked `pose` among them; with several map polygons the rest
  /// of the map can tell them apart (the caller's evidence).
  std::vector<Pose> rotations;
};

/// Two pose hypotheses within 3 % of the distance and 3 deg are the same (the initialiser's
/// ambiguity tests: between map polygons, and between a symmetric polygon's rotations).
inline bool sameHypothesis(const Pose& a, const Pose& b) { return posesAgree(b, a, 0.03, 3.0); }

/// How upright `pose` sees the points `world` (e.g. a polygon's corners): the cosine between
/// the projected map `up` at their centre and the image's up (-y); -1 when behind the camera.
double upScore(const Pose& pose, const PinholeK& k, const std::vector<Eigen::Vector3d>& world,
               const Eigen::Vector3d& up);

/// Corners' reprojection RMS (px) of `pose`.
double cornerReprojectionRms(const Pose& pose, const PinholeK& k, const std::vector<Eigen::Vector2d>& image,
                             const std::vector<Eigen::Vector3d>& world);

/// Returns false when no assignment of the image corners to any map polygon with the same
/// number of corners reprojects within the limit.
/// `only_polygon` >= 0: match the corners to that map polygon only.
bool estimateInitialPose(const std::vector<Eigen::Vector2d>& corners_ideal_px, const LineMap& map, const PinholeK& k,
                         const PoseInitParams& params, InitialPose& result, int only_polygon = -1);

/// The same from an open polygon (one side out of view; polygon_search.h findOpenPolygons): its
/// two missing corners are first placed along the outer sides at the mean length of the sides
/// in view, the completed corners solved as above (with a tolerance for that
/// guess), and the pose then refined so that the corners in view reproject onto theirs and the
/// missing ones onto their sides' lines (2n - 2 residuals for 6 unknowns: n >= 4). The fit
/// must reach max_reprojection_rms_px, and the missing side must lie beyond the outer sides'
/// detected ends. `reprojection_rms_px` is that fit's; `alternatives` as above.
bool estimateInitialPoseOpen(const ImagePolygon& open, const LineMap& map, const PinholeK& k,
                             const PoseInitParams& params, InitialPose& result, int only_polygon = -1);

/// Ceres refinement of T_cam_world minimising the corners' reprojection error.
Pose refinePoseReprojection(const Pose& initial, const PinholeK& k,
                                  const std::vector<Eigen::Vector2d>& image, const std::vector<Eigen::Vector3d>& world);
}  // namespace dvs_line_tracker
