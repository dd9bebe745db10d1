#include <dvs_line_tracker/estimator_state.h>

#include <Eigen/Cholesky>

namespace dvs_line_tracker
{
void TrackingGeometry::indexSharedEndpoints()
{
  const auto& segs = map.segments;
  shared_endpoint.assign(2 * segs.size(), -1);
  auto point = [&](int code) -> const Eigen::Vector3d& {
    return code % 2 == 0 ? segs[code / 2].p0_world : segs[code / 2].p1_world;
  };
  for (int code = 0; code < static_cast<int>(shared_endpoint.size()); ++code)
    for (int earlier = 0; earlier < code - code % 2; ++earlier)
      if (point(earlier) == point(code))
      {
        shared_endpoint[code] = earlier;
        break;
      }
}

void TrackingGeometry::project(const Pose& pose, bool update_visibility, std::vector<ProjectedSegment>& out) const
{
  const double w = width, h = height;
  const bool shared = shared_endpoint.size() == 2 * map.segments.size();
  // An endpoint's camera point, from the earlier segment sharing it when there is one (and did
  // not clip it away); its pixel likewise when that point was in front (then it was projected).
  auto endpoint = [&](int code, const Eigen::Vector3d& world, Eigen::Vector3d& pc, Eigen::Vector2d& px) {
    const int from = shared ? shared_endpoint[code] : -1;
    const ProjectedSegment* o = from >= 0 ? &out[from / 2] : nullptr;
    if (o == nullptr || (from % 2 == 0 ? o->t0 != 0 : o->t1 != 1))
    {
      pc = pose.toCamera(world);
      return false;
    }
    pc = from % 2 == 0 ? o->pc0 : o->pc1;
    if (!o->in_front)
      return false;
    px = from % 2 == 0 ? o->a : o->b;
    return true;
  };
  for (size_t i = 0; i < map.segments.size(); ++i)
  {
    ProjectedSegment& s = out[i];
    Eigen::Vector2d a, b;
    bool have_a = endpoint(static_cast<int>(2 * i), map.segments[i].p0_world, s.pc0, a);
    bool have_b = endpoint(static_cast<int>(2 * i + 1), map.segments[i].p1_world, s.pc1, b);
    const bool front0 = s.pc0.z() > min_depth_m, front1 = s.pc1.z() > min_depth_m;
    s.t0 = 0;
    s.t1 = 1;
    s.in_front = front0 || front1;
    if (!s.in_front)
    {
      s.visible = false;
      s.visible_length = 0;
      continue;
    }
    if (!front0 || !front1)
    {
      // Clip the end behind at the near plane (on the segment: the same image line).
      const double t = (min_depth_m - s.pc0.z()) / (s.pc1.z() - s.pc0.z());
      const Eigen::Vector3d clip = s.pc0 + t * (s.pc1 - s.pc0);
      if (!front0)
      {
        s.t0 = t;
        s.pc0 = clip;
        have_a = false;
      }
      else
      {
        s.t1 = t;
        s.pc1 = clip;
        have_b = false;
      }
    }
    s.set(have_a ? a : k.project(s.pc0), have_b ? b : k.project(s.pc1));
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
  partial_view = false;
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
