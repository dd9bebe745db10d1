#include <dvs_line_tracker/pose_estimator.h>

#include <cmath>

namespace dvs_line_tracker
{
namespace
{
/// Segment endpoints closer to the camera plane (or behind it) are not linearised.
constexpr double kMinLinearizationDepth = 1e-3;
}  // namespace

void projectAlongNormal(const PinholeK& k, const Eigen::Vector3d& p, const Eigen::Vector2d& n, Vector6d& row)
{
  // q = n^T d(px)/d(p_cam); d(p_cam)/d(w, v) = [-[p]x  I], so n^T J = (p x q, q).
  const double iz = 1.0 / p.z();
  const double qx = n.x() * k.fx * iz, qy = n.y() * k.fy * iz;
  const double qz = -(qx * p.x() + qy * p.y()) * iz;
  row << p.y() * qz - p.z() * qy, p.z() * qx - p.x() * qz, p.x() * qy - p.y() * qx, qx, qy, qz;
}

bool linearizeSegment(const PinholeK& k, const Pose& pose, const Eigen::Vector3d& p0_world,
                      const Eigen::Vector3d& p1_world, const PointMoments& moments, int num_points,
                      SegmentNormalEquations& out)
{
  const Eigen::Vector3d pc0 = pose.toCamera(p0_world), pc1 = pose.toCamera(p1_world);
  const bool front = pc0.z() >= kMinLinearizationDepth && pc1.z() >= kMinLinearizationDepth;
  return linearizeSegment(k, pc0, pc1, front ? k.project(pc0) : Eigen::Vector2d::Zero(),
                          front ? k.project(pc1) : Eigen::Vector2d::Zero(), moments, num_points, out);
}

bool linearizeSegment(const PinholeK& k, const Eigen::Vector3d& pc0, const Eigen::Vector3d& pc1,
                      const Eigen::Vector2d& a, const Eigen::Vector2d& b, const PointMoments& moments,
                      int num_points, SegmentNormalEquations& out)
{
  out.num_points = num_points;
  // Zeroed only when nothing is linearised: on success every entry is written below.
  auto none = [&out] {
    out.H.setZero();
    out.g.setZero();
    out.sum_sq = 0;
    return false;
  };
  if (pc0.z() < kMinLinearizationDepth || pc1.z() < kMinLinearizationDepth)
    return none();
  const Eigen::Vector2d e = b - a;
  const double len = e.norm();
  if (len < 1e-6 || num_points < 2)
    return none();
  const Eigen::Vector2d ehat = e / len;
  const Eigen::Vector2d n(-ehat.y(), ehat.x());
  // Per point i (weight w_i, s_i its position along a->b in units of the length, r_i its
  // residual n^T (p_i - a)): J_i = -(A + s_i B) with A = n^T Ja, B = n^T (Jb - Ja) the same for
  // all points. H and g need only the weighted sums of 1, s, s^2, r, r s, which follow from the
  // buffer's raw moments: with d_i = p_i - a, sum w d = m1 - W a and sum w d d^T = M2 - m1 a^T -
  // a m1^T + W a a^T.
  const PointMoments& m = moments;
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
  Vector6d A, B;
  projectAlongNormal(k, pc0, n, A);
  projectAlongNormal(k, pc1, n, B);
  B -= A;
  // H = sw A^T A + sws (A^T B + B^T A) + swss B^T B = A^T u + B^T v (two outer products).
  const Vector6d u = sw * A + sws * B, v = sws * A + swss * B;
  out.H.noalias() = A * u.transpose();
  out.H.noalias() += B * v.transpose();
  out.g.noalias() = -(swr * A + swrs * B);
  return sw > 0;
}

bool factorDampedInformation(const SegmentNormalEquations* eqs, int n, double damping, DampedFactor& f)
{
  f.valid = false;
  Matrix6d H = Matrix6d::Zero();
  int used = 0;
  for (int i = 0; i < n; ++i)
  {
    if (!eqs[i].active)
      continue;
    H += eqs[i].H;
    ++used;
  }
  if (used == 0)
    return false;
  f.information_diagonal = H.diagonal();
  // Marquardt's scaling: each parameter is damped relative to its own information, so the
  // damping does not depend on the units (rad vs. m) and does not favour explaining an image
  // motion by a rotation rather than by a translation.
  H.diagonal().array() *= 1.0 + damping;
  H.diagonal().array() += 1e-9;
  // L D L^T (L unit lower triangular), written out for the fixed size: no square roots, so
  // the chain from column to column is one division (Eigen's LDLT pivots and runs generic
  // loops). The lower triangle of H is read; L(i, c) * D(c) is kept in `ld` for the updates.
  double L[6][6], ld[6][6], inv_diag[6];
  for (int j = 0; j < 6; ++j)
  {
    double d = H(j, j);
    for (int c = 0; c < j; ++c)
      d -= L[j][c] * ld[j][c];
    if (!(d > 0))
      return false;
    inv_diag[j] = 1.0 / d;
    for (int i = j + 1; i < 6; ++i)
    {
      double s = H(i, j);
      for (int c = 0; c < j; ++c)
        s -= L[i][c] * ld[j][c];
      ld[i][j] = s;
      L[i][j] = s * inv_diag[j];
    }
  }
  // The inverse, L^-T D^-1 L^-1, so that each solve is one matrix-vector product (the two
  // triangular substitutions were a dependency chain per solve; the inverse is made once per
  // factor and serves factor_every_solves solves).
  double li[6][6];  // L^-1, unit lower triangular
  for (int j = 0; j < 6; ++j)
  {
    li[j][j] = 1.0;
    for (int i = j + 1; i < 6; ++i)
    {
      double s = -L[i][j];
      for (int k = j + 1; k < i; ++k)
        s -= L[i][k] * li[k][j];
      li[i][j] = s;
    }
  }
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b <= a; ++b)
    {
      double s = 0;
      for (int k = a; k < 6; ++k)
        s += li[k][a] * inv_diag[k] * li[k][b];
      f.inverse(a, b) = f.inverse(b, a) = s;
    }
  f.valid = true;
  return true;
}

namespace
{
/// The active segments' gradient carried to `x_now`, and (kWithInformation) their summed
/// information; false when none is active. (A template: a run-time test in the loop cost the
/// tracking 1.5 %.)
template <bool kWithInformation>
bool accumulateGradient(const SegmentNormalEquations* eqs, int n, const Vector6d& x_now, Vector6d& g,
                        Matrix6d* information)
{
  g.setZero();
  if constexpr (kWithInformation)
    information->setZero();
  int used = 0;
  for (int i = 0; i < n; ++i)
  {
    if (!eqs[i].active)
      continue;
    g.noalias() += eqs[i].g + eqs[i].H * (x_now - eqs[i].x_lin);
    if constexpr (kWithInformation)
      *information += eqs[i].H;
    ++used;
  }
  return used > 0;
}
}  // namespace

bool gradientAt(const SegmentNormalEquations* eqs, int n, const Vector6d& x_now, Vector6d& g)
{
  return accumulateGradient<false>(eqs, n, x_now, g, nullptr);
}

bool gradientAndInformationAt(const SegmentNormalEquations* eqs, int n, const Vector6d& x_now, Vector6d& g,
                              Matrix6d& information)
{
  return accumulateGradient<true>(eqs, n, x_now, g, &information);
}

bool solveWithFactor(const DampedFactor& f, const Vector6d& g, Vector6d& delta)
{
  if (!f.valid)
    return false;
  delta.noalias() = -(f.inverse * g);
  return delta.allFinite();
}

bool solveStep(const SegmentNormalEquations* eqs, int n, const Vector6d& x_now, double damping, Vector6d& delta)
{
  DampedFactor f;
  Vector6d g;
  return factorDampedInformation(eqs, n, damping, f) && gradientAt(eqs, n, x_now, g) && solveWithFactor(f, g, delta);
}
}  // namespace dvs_line_tracker
