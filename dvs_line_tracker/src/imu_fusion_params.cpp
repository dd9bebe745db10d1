#include <dvs_line_tracker/imu_fusion_params.h>
#include <dvs_line_tracker/vector_params.h>

namespace dvs_line_tracker
{
std::string parseImuExtrinsics(const ImuFusionParams& p, ImuExtrinsics& out)
{
  const std::string err = parseRotationTranslation(p.q_camera_imu, "imu_q_camera_imu", p.p_camera_imu,
                                                   "imu_p_camera_imu", out.R_camera_imu, out.p_camera_imu);
  if (!err.empty())
    return err;
  out.gravity_world.reset();
  double g[3];
  if (p.gravity_world.find_first_not_of(" \t") != std::string::npos)
  {
    if (!parseNumbers(p.gravity_world, 3, g))
      return "imu_gravity_world must be empty (estimated) or 3 numbers 'x y z' in m/s^2 (got '" + p.gravity_world + "')";
    const Eigen::Vector3d gw(g[0], g[1], g[2]);
    if (gw.norm() < 9.0 || gw.norm() > 10.5)
      return "imu_gravity_world must have a magnitude near 9.81 m/s^2 (got " + std::to_string(gw.norm()) + ")";
    out.gravity_world = gw;
  }
  return "";
}
}  // namespace dvs_line_tracker
