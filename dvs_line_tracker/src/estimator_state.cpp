#include <dvs_line_tracker/estimator_state.h>

#include <Eigen/Cholesky>

namespace dvs_line_tracker
{
void TrackingGeometry::project(const Pose& pose, bool update_visibility, std::vector<ProjectedSegment>& out) const
{
  const double w = width, h = height;
  for (size_t i = 0; i < map.segments.size(); ++i)
  {
    ProjectedSegment& s = out[i];
    const Eigen::Vector3d pc0 = pose.toCamera(map.segments[i].p0_world);
    const Eigen::Vector3d pc1 = pose.toCamera(map.segments[i].p1_world);
    s.in_front = pc0.z() > min_depth_m && pc1.z() > min_depth_m;
    if (!s.in_front)
    {
      s.visible = false;
      s.visible_length = 0;
      continue;
    }
    s.set(k.project(pc0), k.project(pc1));
    if (update_visibility)
    {
      s.visible_length = clippedLength(s.a, s.b, -0.5, -0.5, w - 0.5, h - 0.5);
      s.visible = s.visible_length >= min_visible_length_px;
    }
  }
}

double TrackingGeometry::clippedSegment(const ProjectedSegment& s, Eigen::Vector2d* a, Eigen::Vector2d* b) const
{
  return clippedLength(s.a, s.b, -0.5, -0.5, width - 0.5, height - 0.5, a, b);
}

void EstimatorState::resize(size_t segments, int buffer_size)
{
  projected.assign(segments, ProjectedSegment());
  buffers.assign(segments, SegmentBuffer(buffer_size));
  equations.assign(segments, SegmentNormalEquations());
  x_accumulated.setZero();
  damping = 0;
}

void EstimatorState::clear()
{
  for (auto& b : buffers)
    b.clear();
  for (auto& e : equations)
    e = SegmentNormalEquations();
  x_accumulated.setZero();
}

int EstimatorState::visibleSegments() const
{
  int visible = 0;
  for (const auto& s : projected)
    visible += s.visible ? 1 : 0;
  return visible;
}

Matrix6d visionPoseCovariance(const EstimatorState& state)
{
  // The Gauss-Newton covariance of the buffered events: residual variance x inverse information,
  // in the solver's increment (w, v); then in (rotation error in camera axes, position in the
  // world): an increment (w, v) moves the camera by R_world_camera(-w) and its centre by
  // -R_world_camera v.
  Matrix6d H = Matrix6d::Zero();
  double sum_sq = 0;
  int points = 0;
  for (const auto& eq : state.equations)
  {
    if (!eq.active)
      continue;
    H += eq.H;
    sum_sq += eq.sum_sq;
    points += eq.num_points;
  }
  const double sigma2 = points > 6 ? std::max(sum_sq / (points - 6), 0.01) : 1.0;
  H.diagonal().array() += 1e-9;
  Matrix6d cov_wv = Eigen::LLT<Matrix6d>(H).solve(Matrix6d::Identity()) * sigma2;
  Matrix6d J = Matrix6d::Zero();
  J.block<3, 3>(0, 0) = -Eigen::Matrix3d::Identity();
  J.block<3, 3>(3, 3) = -state.pose.R_world_camera();
  Matrix6d c = J * cov_wv * J.transpose();
  // A floor (before the scales): 0.005 mm / 0.0003 deg, against a degenerate information.
  c.diagonal().head<3>().array() += 3e-11;
  c.diagonal().tail<3>().array() += 3e-11;
  return 0.5 * (c + c.transpose());
}

}  // namespace dvs_line_tracker
