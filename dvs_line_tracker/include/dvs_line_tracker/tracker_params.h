#pragma once
// The tracker's parameters by name: the one list the offline tool's YAML file, the nodelet's
// ROS parameters and the README's table share.
#include <dvs_line_tracker/line_tracker.h>

#include <functional>
#include <string>

namespace dvs_line_tracker
{
/// Visit every numeric parameter: `name`, a reference to its value (exactly one of the
/// pointers is non-null), and its unit.
struct ParamRef
{
  const char* name;
  double* d = nullptr;
  int* i = nullptr;
  bool* b = nullptr;
  const char* unit = "";
};
void forEachParam(LineTrackerParams& params, const std::function<void(const ParamRef&)>& visit);

/// "incremental" or "full" (anything else: false).
bool parseSolverType(const std::string& name, SolverType& type);
const char* solverTypeName(SolverType type);

/// Read parameters from a flat YAML mapping (names as in forEachParam, plus `solver`).
/// Throws std::runtime_error naming the file and the key on unknown keys or wrong types, and
/// the validation message on invalid values.
void loadTrackerParamsYaml(const std::string& path, LineTrackerParams& params);
}  // namespace dvs_line_tracker
