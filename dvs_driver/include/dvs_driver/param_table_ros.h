#pragma once
// The ROS side of the one parameter mechanism (param_table.h): a table read from a node's
// private namespace, with unknown names warned about and bounds validated.
#include <dvs_driver/param_table.h>

#include <ros/node_handle.h>

#include <string>
#include <vector>

namespace dvs_driver
{
/// Read every entry of `table` from `pnh` (a missing parameter keeps its default), then warn
/// (ROS_WARN, once per name) about every parameter set in `pnh`'s namespace that neither the
/// table nor `also_known` names, then validate. Throws std::invalid_argument naming the
/// parameter on a wrong type or a value out of range. Returns the unknown names.
std::vector<std::string> loadRosParams(const ros::NodeHandle& pnh, ParamTable& table,
                                       const std::vector<std::string>& also_known = {});

/// The names set in `pnh`'s namespace (first component after it) that are neither in `table`
/// nor in `also_known`.
std::vector<std::string> unknownRosParams(const ros::NodeHandle& pnh, const ParamTable& table,
                                          const std::vector<std::string>& also_known = {});
}  // namespace dvs_driver
