#pragma once
// Vector-valued parameters given as text (ROS parameters and YAML keep them as strings, e.g.
// "0 0 0 1"): the one parser of numbers and of a rotation + translation, with errors naming the
// parameter (ROS-free).
#include <Eigen/Core>

#include <string>

namespace dvs_line_tracker
{
/// Exactly `n` finite numbers separated by spaces or commas (brackets allowed) into `out`.
bool parseNumbers(std::string text, int n, double* out);

/// A unit quaternion "x y z w" (parameter `q_name`, norm within 1e-3 of 1, normalised) and a
/// translation "x y z" in metres (parameter `p_name`). Returns "" or a message naming the parameter.
std::string parseRotationTranslation(const std::string& q_text, const std::string& q_name, const std::string& p_text,
                                     const std::string& p_name, Eigen::Matrix3d& R, Eigen::Vector3d& p);
}  // namespace dvs_line_tracker
