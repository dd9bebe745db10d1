#include <dvs_line_tracker/vector_params.h>

#include <Eigen/Geometry>

#include <cmath>
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

std::string parseRotationTranslation(const std::string& q_text, const std::string& q_name, const std::string& p_text,
                                     const std::string& p_name, Eigen::Matrix3d& R, Eigen::Vector3d& p)
{
  double q[4], t[3];
  if (!parseNumbers(q_text, 4, q))
    return q_name + " must be 4 numbers 'x y z w' (got '" + q_text + "')";
  const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
  if (std::abs(quat.norm() - 1.0) > 1e-3)
    return q_name + " must be a unit quaternion (norm " + std::to_string(quat.norm()) + ")";
  if (!parseNumbers(p_text, 3, t))
    return p_name + " must be 3 numbers 'x y z' in metres (got '" + p_text + "')";
  R = quat.normalized().toRotationMatrix();
  p = Eigen::Vector3d(t[0], t[1], t[2]);
  return "";
}
}  // namespace dvs_line_tracker
