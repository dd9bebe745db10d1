#include <dvs_screen_sim/screen_loop/alignment.h>
#include <dvs_screen_sim/screen_loop/projection_pipeline.h>

#include <Eigen/Dense>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <string>

namespace dvs_screen_sim
{
namespace screen_loop
{
namespace
{
/// Similarity moving the centroid to 0 and the mean distance to sqrt(2).
Eigen::Matrix3d normalizer(const Points2d& p)
{
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& q : p)
    c += q;
  c /= static_cast<double>(p.size());
  double d = 0;
  for (const auto& q : p)
    d += (q - c).norm();
  d /= static_cast<double>(p.size());
  if (!(d > 1e-15))
    throw AlignmentError("fitHomography: all points coincide");
  const double s = std::sqrt(2.0) / d;
  Eigen::Matrix3d T;
  T << s, 0, -s * c.x(), 0, s, -s * c.y(), 0, 0, 1;
  return T;
}
}  // namespace

Eigen::Matrix3d fitHomography(const Points2d& src, const Points2d& dst)
{
  if (src.size() != dst.size())
    throw AlignmentError("fitHomography: " + std::to_string(src.size()) + " source but " +
                         std::to_string(dst.size()) + " destination points");
  if (src.size() < 4)
    throw AlignmentError("fitHomography: needs at least 4 correspondences (got " + std::to_string(src.size()) + ")");
  for (size_t i = 0; i < src.size(); ++i)
    if (!src[i].allFinite() || !dst[i].allFinite())
      throw AlignmentError("fitHomography: point " + std::to_string(i) + " is not finite");
  const Eigen::Matrix3d Ts = normalizer(src), Td = normalizer(dst);
  const size_t n = src.size();
  Eigen::MatrixXd A(2 * n, 9);
  for (size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector3d s = Ts * src[i].homogeneous();
    const Eigen::Vector3d d = Td * dst[i].homogeneous();
    A.row(2 * i) << 0, 0, 0, -d.z() * s.transpose(), d.y() * s.transpose();
    A.row(2 * i + 1) << d.z() * s.transpose(), 0, 0, 0, -d.x() * s.transpose();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  // A rank below 8 means the points do not determine a homography (e.g. all collinear).
  if (sv(7) < 1e-9 * sv(0))
    throw AlignmentError("fitHomography: degenerate point configuration (collinear points?)");
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d Hn;
  Hn << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  Eigen::Matrix3d H = Td.inverse() * Hn * Ts;
  H = normalizeHomography(H);

  // Gauss-Newton on the transfer error (8 parameters, h33 fixed to 1 when it is not ~0).
  if (std::abs(H(2, 2)) > 1e-6)
  {
    for (int it = 0; it < 10; ++it)
    {
      Eigen::Matrix<double, 8, 8> JtJ = Eigen::Matrix<double, 8, 8>::Zero();
      Eigen::Matrix<double, 8, 1> Jtr = Eigen::Matrix<double, 8, 1>::Zero();
      for (size_t i = 0; i < n; ++i)
      {
        const Eigen::Vector3d q = H * src[i].homogeneous();
        const double x = src[i].x(), y = src[i].y(), w = q.z();
        const Eigen::Vector2d r(q.x() / w - dst[i].x(), q.y() / w - dst[i].y());
        Eigen::Matrix<double, 2, 8> J;
        const double u = q.x() / w, v = q.y() / w;
        J << x / w, y / w, 1 / w, 0, 0, 0, -u * x / w, -u * y / w,  //
            0, 0, 0, x / w, y / w, 1 / w, -v * x / w, -v * y / w;
        JtJ += J.transpose() * J;
        Jtr += J.transpose() * r;
      }
      const Eigen::Matrix<double, 8, 1> delta = JtJ.ldlt().solve(-Jtr);
      if (!delta.allFinite())
        break;
      Eigen::Matrix3d Hn2 = H;
      Hn2(0, 0) += delta(0); Hn2(0, 1) += delta(1); Hn2(0, 2) += delta(2);
      Hn2(1, 0) += delta(3); Hn2(1, 1) += delta(4); Hn2(1, 2) += delta(5);
      Hn2(2, 0) += delta(6); Hn2(2, 1) += delta(7);
      if (transferError(Hn2, src, dst).rms > transferError(H, src, dst).rms)
        break;
      H = Hn2;
      if (delta.norm() < 1e-14 * (1 + H.norm()))
        break;
    }
  }
  return H;
}

TransferError transferError(const Eigen::Matrix3d& H, const Points2d& src, const Points2d& dst)
{
  TransferError e;
  if (src.empty())
    return e;
  double ss = 0, s = 0;
  for (size_t i = 0; i < src.size(); ++i)
  {
    const double d = (applyHomography(H, src[i]) - dst[i]).norm();
    ss += d * d;
    s += d;
    e.max = std::max(e.max, d);
  }
  e.rms = std::sqrt(ss / src.size());
  e.mean = s / src.size();
  return e;
}

AlignmentResult computeAlignment(const Points2d& measured_ideal_px, const Points2d& displayed_vp,
                                 const Points2d& desired_ideal_px)
{
  if (desired_ideal_px.size() != displayed_vp.size())
    throw AlignmentError("computeAlignment: " + std::to_string(displayed_vp.size()) + " displayed but " +
                         std::to_string(desired_ideal_px.size()) + " desired points");
  AlignmentResult r;
  r.points = displayed_vp.size();
  r.H_D = fitHomography(measured_ideal_px, displayed_vp);                          // Eq. 3.11
  r.residual_dvs_px = transferError(r.H_D.inverse(), displayed_vp, measured_ideal_px);
  Points2d desired_vp(desired_ideal_px.size());
  for (size_t i = 0; i < desired_ideal_px.size(); ++i)
    desired_vp[i] = applyHomography(r.H_D, desired_ideal_px[i]);                   // Eq. 3.13
  r.H = normalizeHomography(fitHomography(displayed_vp, desired_vp));              // Eq. 3.14
  return r;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
