#pragma once
// The per-event pose update (thesis 4.2.2 "Pose Estimation"): minimise the distances of the
// buffered events to their projected segments over the 6-DoF camera pose, warm-started from
// the previous pose.
//
// Incremental solver (default): every segment keeps its Gauss-Newton normal-equation
// contribution (H_i = sum J^T J, g_i = sum J^T r) linearised at the pose of its last update.
// After an event only the changed segment (plus one more, round robin) is re-linearised; the
// stale contributions are carried to the current pose to first order (g_i + H_i (x - x_i),
// x the accumulated increments), and one damped Gauss-Newton step is taken. Per event this
// costs two segment linearisations and one 6x6 solve, and allocates nothing.
// Full solver (for comparison): re-linearise all segments and iterate Gauss-Newton.
#include <dvs_line_tracker/pose_types.h>
#include <dvs_line_tracker/pose_initializer.h>
#include <dvs_line_tracker/segment_attribution.h>

#include <vector>

namespace dvs_line_tracker
{
enum class SolverType
{
  kIncremental,   ///< one Gauss-Newton step per event on cached per-segment contributions
  kFullGaussNewton  ///< all segments re-linearised, several iterations per event
};

struct PoseEstimatorParams
{
  SolverType solver = SolverType::kIncremental;
  int full_iterations = 3;       ///< Gauss-Newton iterations per event for kFullGaussNewton
  int extra_relinearizations = 1;///< incremental: segments re-linearised round robin per event besides the changed one
  double damping = 0.07;         ///< Levenberg-Marquardt damping, relative to each diagonal element of H (steadies weakly observable directions; more lags, BENCHMARKS.md)
  double huber_px = 0.5;         ///< Huber threshold of the point-to-line residuals (weights fixed when an event is buffered; 0.5 measured better than 1, BENCHMARKS.md)
};

struct SegmentNormalEquations
{
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  Vector6d x_lin = Vector6d::Zero();  ///< accumulated increments at linearisation
  double sum_sq = 0;                   ///< weighted sum of squared residuals at linearisation
  int num_points = 0;
  bool active = false;
};

/// n^T J for a unit image direction `n`, J the Jacobian of the projection of camera point `p_cam`
/// with respect to the pose increment (w, v): the row a point-to-line residual along n needs,
/// without forming the 2x6 Jacobian.
void projectAlongNormal(const PinholeK& k, const Eigen::Vector3d& p_cam, const Eigen::Vector2d& n, Vector6d& row);

/// Normal-equation contribution of the points of one buffer to its segment at `pose`, from the
/// buffer's weighted moments (O(1), whatever the buffer size; the Huber weights were fixed when
/// the points were inserted, stale points are removed by the buffer's motion bound). Returns
/// false when the segment is behind the camera, degenerate, or has fewer than 2 points.
/// (From the weighted moments of `num_points` points: what a buffer keeps; a one-off fit needs
/// no buffer, e.g. the initialiser's refinement.)
bool linearizeSegment(const PinholeK& k, const Pose& pose, const Eigen::Vector3d& p0_world,
                      const Eigen::Vector3d& p1_world, const PointMoments& moments, int num_points,
                      SegmentNormalEquations& out);
inline bool linearizeSegment(const PinholeK& k, const Pose& pose, const Eigen::Vector3d& p0_world,
                             const Eigen::Vector3d& p1_world, const SegmentBuffer& buffer, SegmentNormalEquations& out)
{
  return linearizeSegment(k, pose, p0_world, p1_world, buffer.moments(), buffer.size(), out);
}
/// The same from the segment's endpoints already in the camera frame (`pc0`, `pc1`) and their
/// pixels (`a`, `b`: k.project of them, needed only when both lie in front).
bool linearizeSegment(const PinholeK& k, const Eigen::Vector3d& pc0, const Eigen::Vector3d& pc1,
                      const Eigen::Vector2d& a, const Eigen::Vector2d& b, const PointMoments& moments,
                      int num_points, SegmentNormalEquations& out);
inline bool linearizeSegment(const PinholeK& k, const Eigen::Vector3d& pc0, const Eigen::Vector3d& pc1,
                             const Eigen::Vector2d& a, const Eigen::Vector2d& b, const SegmentBuffer& buffer,
                             SegmentNormalEquations& out)
{
  return linearizeSegment(k, pc0, pc1, a, b, buffer.moments(), buffer.size(), out);
}

/// Solve the damped normal equations of the active segments at the accumulated increment
/// `x_now`. Returns false when there is nothing to solve.
bool solveStep(const SegmentNormalEquations* eqs, int n, const Vector6d& x_now, double damping, Vector6d& delta);

/// The damped information matrix sum H_i (diagonal scaled by 1 + damping), factored (L D L^T)
/// and kept as its inverse: solveStep in parts, so that a factor can serve several steps while
/// the information changes little (only the gradient is then assembled per step).
struct DampedFactor
{
  Matrix6d inverse = Matrix6d::Zero();  ///< (L D L^T)^-1
  Vector6d information_diagonal = Vector6d::Zero();  ///< the diagonal of the sum H_i factored (undamped)
  bool valid = false;
};
/// Factor the damped information of the active segments; false when none is active or the
/// matrix is not positive definite (then `f` is invalid).
bool factorDampedInformation(const SegmentNormalEquations* eqs, int n, double damping, DampedFactor& f);
/// The gradient of the active segments carried to `x_now` (sum g_i + H_i (x_now - x_lin_i));
/// false when none is active.
bool gradientAt(const SegmentNormalEquations* eqs, int n, const Vector6d& x_now, Vector6d& g);
/// gradientAt, and the summed information of the active segments (sum H_i) in the same pass:
/// the gradient at x_now + d is then g + H d, whatever the number of segments.
bool gradientAndInformationAt(const SegmentNormalEquations* eqs, int n, const Vector6d& x_now, Vector6d& g,
                              Matrix6d& information);
/// delta = -(L D L^T)^-1 g (the factor's inverse times g); false when `f` is invalid or the result is not finite.
bool solveWithFactor(const DampedFactor& f, const Vector6d& g, Vector6d& delta);
}  // namespace dvs_line_tracker
