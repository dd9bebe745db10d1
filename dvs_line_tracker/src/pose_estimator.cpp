#include <dvs_line_tracker/pose_estimator.h>

#include <Eigen/Cholesky>

namespace dvs_line_tracker
{
void projectWithJacobian(const PinholeK& k, const Eigen::Vector3d& p, Eigen::Vector2d& px, Matrix26d& J)
{
  const double iz = 1.0 / p.z();
  const double x = p.x() * iz, y = p.y() * iz;
  px = Eigen::Vector2d(k.fx * x + k.cx, k.fy * y + k.cy);
  // d(px)/d(p_cam) = [fx/z 0 -fx x/z; 0 fy/z -fy y/z]; d(p_cam)/d(w, v) = [-[p]x  I].
  Eigen::Matrix<double, 2, 3> dpi;
  dpi << k.fx * iz, 0, -k.fx * x * iz, 0, k.fy * iz, -k.fy * y * iz;
  Eigen::Matrix3d minus_skew;
  minus_skew << 0, p.z(), -p.y(), -p.z(), 0, p.x(), p.y(), -p.x(), 0;
  J.leftCols<3>() = dpi * minus_skew;
  J.rightCols<3>() = dpi;
}

bool linearizeSegment(const PinholeK& k, const CameraPose& pose, const Eigen::Vector3d& p0_world,
                      const Eigen::Vector3d& p1_world, const SegmentBuffer& buffer, double huber_px,
                      SegmentNormalEquations& out, double gate_px)
{
  out.H.setZero();
  out.g.setZero();
  out.sum_sq = 0;
  out.num_points = 0;
  const Eigen::Vector3d pc0 = pose.toCamera(p0_world), pc1 = pose.toCamera(p1_world);
  if (pc0.z() < 1e-3 || pc1.z() < 1e-3)
    return false;
  Eigen::Vector2d a, b;
  Matrix26d Ja, Jb;
  projectWithJacobian(k, pc0, a, Ja);
  projectWithJacobian(k, pc1, b, Jb);
  const Eigen::Vector2d e = b - a;
  const double len = e.norm();
  if (len < 1e-6 || buffer.size() == 0)
    return false;
  const Eigen::Vector2d ehat = e / len;
  const Eigen::Vector2d n(-ehat.y(), ehat.x());
  // Per point J = -(A + s B) with A = n^T Ja, B = n^T (Jb - Ja) the same for all points of the
  // segment: accumulate scalar moments per point and build H, g from three outer products.
  const Eigen::Matrix<double, 1, 6> A = n.transpose() * Ja;
  const Eigen::Matrix<double, 1, 6> B = n.transpose() * Jb - A;
  double sw = 0, sws = 0, swss = 0, swr = 0, swrs = 0;
  for (int i = 0; i < buffer.size(); ++i)
  {
    const Eigen::Vector2d w = buffer.point(i) - a;
    const double s = ehat.dot(w) / len;
    const double r = n.dot(w);
    const double ar = std::abs(r);
    if (ar > gate_px)
      continue;
    const double weight = ar <= huber_px ? 1.0 : huber_px / ar;
    sw += weight;
    sws += weight * s;
    swss += weight * s * s;
    swr += weight * r;
    swrs += weight * r * s;
    out.sum_sq += r * r;
    ++out.num_points;
  }
  const Eigen::Matrix<double, 6, 1> At = A.transpose(), Bt = B.transpose();
  const Matrix6d AB = At * B;
  out.H.noalias() = sw * (At * A) + sws * (AB + AB.transpose()) + swss * (Bt * B);
  out.g.noalias() = -(swr * At + swrs * Bt);
  return out.num_points >= 2;
}

bool solveStep(const SegmentNormalEquations* eqs, int n, const Vector6d& x_now, double damping, Vector6d& delta)
{
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  int used = 0;
  for (int i = 0; i < n; ++i)
  {
    if (!eqs[i].active)
      continue;
    H += eqs[i].H;
    g.noalias() += eqs[i].g + eqs[i].H * (x_now - eqs[i].x_lin);
    ++used;
  }
  if (used == 0)
    return false;
  const double mean_diag = H.diagonal().mean();
  H.diagonal().array() += damping * mean_diag + 1e-9;
  const Eigen::LLT<Matrix6d> llt(H);
  if (llt.info() != Eigen::Success)
    return false;
  delta = -llt.solve(g);
  return delta.allFinite();
}
}  // namespace dvs_line_tracker
