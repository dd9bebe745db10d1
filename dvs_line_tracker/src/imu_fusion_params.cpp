#include <dvs_line_tracker/imu_fusion_params.h>

#include <sstream>

namespace dvs_line_tracker
{
bool parseNumbers(std::string text, int n, double* out)
{
  for (char& c : text)
    if (c == ',' || c == '[' || c == ']')
      c = ' ';
  std::istringstream in(text);
  for (int i = 0; i < n; ++i)
    if (!(in >> out[i]) || !std::isfinite(out[i]))
      return false;
  std::string rest;
  return !(in >> rest);
}

std::string parseImuExtrinsics(const ImuFusionParams& p, ImuExtrinsics& out)
{
  double q[4], t[3], g[3];
  if (!parseNumbers(p.q_camera_imu, 4, q))
    return "imu_q_camera_imu must be 4 numbers 'x y z w' (got '" + p.q_camera_imu + "')";
  const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
  if (std::abs(quat.norm() - 1.0) > 1e-3)
    return "imu_q_camera_imu must be a unit quaternion (norm " + std::to_string(quat.norm()) + ")";
  if (!parseNumbers(p.p_camera_imu, 3, t))
    return "imu_p_camera_imu must be 3 numbers 'x y z' in metres (got '" + p.p_camera_imu + "')";
  out.R_camera_imu = quat.normalized().toRotationMatrix();
  out.p_camera_imu = Eigen::Vector3d(t[0], t[1], t[2]);
  out.gravity_world.reset();
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
