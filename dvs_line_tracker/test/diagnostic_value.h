#pragma once
// For the tracker rostests: a value of the tracker's diagnostics.
#include <diagnostic_msgs/DiagnosticStatus.h>

#include <string>

/// The value of `key` in a tracker's diagnostics ("" when absent).
inline std::string diagnosticValue(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key)
{
  for (const auto& kv : s.values)
    if (kv.key == key)
      return kv.value;
  return "";
}
