#pragma once
// The per-event estimator's state (in the spirit of open_vins' State: variables, no policy):
// the pose estimate, the accumulated increment since each segment's linearisation, the map
// segments projected at the estimate, the per-segment event buffers and their normal equations,
// and the damping in force. The parts that change it: EventUpdater (per event), LossMonitor
// (reads it), TrackerInitializer (produces the pose it starts from).
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/pose_estimator.h>
#include <dvs_line_tracker/pose_types.h>
#include <dvs_line_tracker/segment_attribution.h>

#include <vector>

namespace dvs_line_tracker
{
/// What the estimator needs of the camera and the map to project segments (immutable).
struct TrackingGeometry
{
  LineMap map;
  PinholeK k;        ///< ideal pinhole (events are undistorted by the camera model's table)
  int width = 0, height = 0;
  double ideal_radius_px = 0;  ///< largest distance of an undistorted sensor pixel from the image centre
  double min_depth_m = 0.05;            ///< the near plane: a map segment crossing it is clipped there
  double min_visible_length_px = 12.0;  ///< shorter visible parts do not count as visible
  /// Per segment, per endpoint (2 i + 0: p0, 2 i + 1: p1): the same map point as an endpoint of an
  /// earlier segment, coded the same way, or -1 (a polygon's sides share their corners). Empty:
  /// none shared. Filled by indexSharedEndpoints().
  std::vector<int> shared_endpoint;

  /// Fill shared_endpoint from the map (call after setting `map`).
  void indexSharedEndpoints();
  /// Project every map segment at `pose` into `out` (sized like the map); a corner shared by
  /// several segments is transformed and projected once. A segment with one endpoint closer
  /// than min_depth_m (or behind the camera) is clipped at that depth: the part in front still
  /// lies on the map segment's image line (a wide lens close to a large target at a steep angle
  /// sees sides whose far ends are behind it); one wholly closer is not in front. With
  /// `update_visibility`, also clip to the image (visible_length, visible); otherwise only the
  /// projection is refreshed (the per-event path).
  void project(const Pose& pose, bool update_visibility, std::vector<ProjectedSegment>& out) const;
  /// The world points the projection of segment `i` used (its endpoints, or where it was clipped).
  void usedEndpoints(int i, const ProjectedSegment& s, Eigen::Vector3d& p0_world, Eigen::Vector3d& p1_world) const
  {
    const MapSegment& m = map.segments[i];
    p0_world = s.t0 == 0 ? m.p0_world : Eigen::Vector3d(m.p0_world + s.t0 * (m.p1_world - m.p0_world));
    p1_world = s.t1 == 1 ? m.p1_world : Eigen::Vector3d(m.p0_world + s.t1 * (m.p1_world - m.p0_world));
  }
  /// Length (px) of the projected segment `s` inside the image; its clipped endpoints into
  /// `a`, `b` when not empty.
  double clippedSegment(const ProjectedSegment& s, Eigen::Vector2d* a, Eigen::Vector2d* b) const;
};

struct EstimatorState
{
  Pose pose;                                       ///< T_world_camera, the estimate
  Vector6d x_accumulated = Vector6d::Zero();       ///< sum of the increments applied (linearisation reference)
  std::vector<ProjectedSegment> projected;         ///< map segments at `projected_at`
  Pose projected_at;                               ///< the pose `projected` was computed at (the IMU moves `pose` without projecting)
  std::vector<SegmentBuffer> buffers;              ///< per segment: its recent events
  std::vector<SegmentNormalEquations> equations;   ///< per segment: its normal equations
  double damping = 0;                              ///< in force (normal or partial view)
  bool partial_view = false;                       ///< part of the map outside the image or behind the camera (the partial view's damping in force)

  /// Sized for `segments` map segments, buffers of `buffer_size` events, everything cleared.
  void resize(size_t segments, int buffer_size);
  /// Empty buffers and equations, pose untouched.
  void clear();
  int visibleSegments() const;
};

/// The Gauss-Newton covariance of the pose the buffered events give (residual variance x inverse
/// information of the active segments' normal equations), over (rotation error in camera axes,
/// right-multiplied; camera position in the world). Its error is not white (the buffers overlap
/// from event to event): the IMU filter scales it (imu_fusion_params.h).
Matrix6d visionPoseCovariance(const EstimatorState& state);
}  // namespace dvs_line_tracker
