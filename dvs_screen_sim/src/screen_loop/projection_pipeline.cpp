#include <dvs_screen_sim/screen_loop/projection_pipeline.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace dvs_screen_sim
{
namespace screen_loop
{
Eigen::Matrix4d viewMatrix(const Pose& T_world_camera)
{
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.topLeftCorner<3, 3>() = T_world_camera.R_camera_world;
  M.topRightCorner<3, 1>() = T_world_camera.t_camera_world;
  return M;
}

VirtualFocalLengths matchedFocalLengths(const dvs_calibration::CameraModel& dvs, double x_scale)
{
  if (dvs.width() < 2 || dvs.height() < 2)
    throw std::invalid_argument("matchedFocalLengths: the camera must be at least 2x2 pixels");
  if (!(x_scale > 0) || !std::isfinite(x_scale))
    throw std::invalid_argument("matchedFocalLengths: x_scale must be positive (got " + std::to_string(x_scale) + ")");
  VirtualFocalLengths f;
  f.fx = x_scale * dvs.intrinsics().fx * 2.0 / (dvs.width() - 1);
  f.fy = -dvs.intrinsics().fy * 2.0 / (dvs.height() - 1);
  return f;
}

Eigen::Matrix4d projectionMatrix(const VirtualFocalLengths& f)
{
  Eigen::Matrix4d K = Eigen::Matrix4d::Zero();
  K(0, 0) = f.fx;
  K(1, 1) = f.fy;
  K(3, 2) = 1.0;
  return K;
}

Eigen::Matrix4d expandHomography(const Eigen::Matrix3d& H)
{
  Eigen::Matrix4d E = Eigen::Matrix4d::Zero();
  const int rows[3] = {0, 1, 3};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      E(rows[i], rows[j]) = H(i, j);
  E(2, 2) = 1.0;
  return E;
}

Eigen::Matrix3d normalizeHomography(const Eigen::Matrix3d& H)
{
  if (!H.allFinite())
    throw std::invalid_argument("homography has non-finite elements");
  if (std::abs(H(2, 2)) > 1e-12 * H.norm())
    return H / H(2, 2);
  const double n = H.norm();
  if (n == 0)
    throw std::invalid_argument("homography is zero");
  return H / n;
}

ProjectionPipeline::ProjectionPipeline(const dvs_calibration::CameraModel& dvs, double x_scale)
  : f_(matchedFocalLengths(dvs, x_scale))
{
  const auto& k = dvs.intrinsics();
  A_ << k.fx / f_.fx, 0, k.cx, 0, k.fy / f_.fy, k.cy, 0, 0, 1;
}

Eigen::Vector4d ProjectionPipeline::clip(const Pose& T_world_camera, const Eigen::Vector3d& p_world, bool corrected) const
{
  const Eigen::Matrix4d P = corrected ? correctedProjection() : projection();
  return P * viewMatrix(T_world_camera) * p_world.homogeneous();
}

bool ProjectionPipeline::viewport(const Pose& T_world_camera, const Eigen::Vector3d& p_world, Eigen::Vector2d& vp,
                                  bool corrected) const
{
  const Eigen::Vector4d c = clip(T_world_camera, p_world, corrected);
  if (!(c.w() > 1e-12))
    return false;
  vp = Eigen::Vector2d(c.x() / c.w(), c.y() / c.w());
  return true;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
