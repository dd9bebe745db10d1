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

bool linearizeSegment(const PinholeK& k, const Pose& pose, const Eigen::Vector3d& p0_world,
                      const Eigen::Vector3d& p1_world, const SegmentBuffer& buffer, SegmentNormalEquations& out)
{
  out.H.setZero();
  out.g.setZero();
  out.sum_sq = 0;
  out.num_points = buffer.size();
  const Eigen::Vector3d pc0 = pose.toCamera(p0_world), pc1 = pose.toCamera(p1_world);
  if (pc0.z() < 1e-3 || pc1.z() < 1e-3)
    return false;
  Eigen::Vector2d a, b;
  Matrix26d Ja, Jb;
  projectWithJacobian(k, pc0, a, Ja);
  projectWithJacobian(k, pc1, b, Jb);
  const Eigen::Vector2d e = b - a;
  const double len = e.norm();
  if (len < 1e-6 || buffer.size() < 2)
    return false;
  const Eigen::Vector2d ehat = e / len;
  const Eigen::Vector2d n(-ehat.y(), ehat.x());
  // Per point i (weight w_i, s_i its position along a->b in units of the length, r_i its
  // residual n^T (p_i - a)): J_i = -(A + s_i B) with A = n^T Ja, B = n^T (Jb - Ja) the same for
  // all points. H and g need only the weighted sums of 1, s, s^2, r, r s, which follow from the
  // buffer's raw moments: with d_i = p_i - a, sum w d = m1 - W a and sum w d d^T = M2 - m1 a^T -
  // a m1^T + W a a^T.
  const PointMoments& m = buffer.moments();
  const Eigen::Vector2d m1(m.x, m.y);
  const Eigen::Vector2d d1 = m1 - m.w * a;
  Eigen::Matrix2d M2;
  M2 << m.xx, m.xy, m.xy, m.yy;
  const Eigen::Matrix2d D2 = M2 - m1 * a.transpose() - a * m1.transpose() + m.w * a * a.transpose();
  const double sw = m.w;
  const double sws = ehat.dot(d1) / len;
  const double swss = ehat.dot(D2 * ehat) / (len * len);
  const double swr = n.dot(d1);
  const double swrs = n.dot(D2 * ehat) / len;
  out.sum_sq = n.dot(D2 * n);
  const Eigen::Matrix<double, 1, 6> A = n.transpose() * Ja;
  const Eigen::Matrix<double, 1, 6> B = n.transpose() * Jb - A;
  const Eigen::Matrix<double, 6, 1> At = A.transpose(), Bt = B.transpose();
  const Matrix6d AB = At * B;
  out.H.noalias() = sw * (At * A) + sws * (AB + AB.transpose()) + swss * (Bt * B);
  out.g.noalias() = -(swr * At + swrs * Bt);
  return sw > 0;
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
  // Marquardt's scaling: each parameter is damped relative to its own information, so the
  // damping does not depend on the units (rad vs. m) and does not favour explaining an image
  // motion by a rotation rather than by a translation.
  H.diagonal().array() *= 1.0 + damping;
  H.diagonal().array() += 1e-9;
  const Eigen::LLT<Matrix6d> llt(H);
  if (llt.info() != Eigen::Success)
    return false;
  delta = -llt.solve(g);
  return delta.allFinite();
}
}  // namespace dvs_line_tracker
