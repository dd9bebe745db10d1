// The tracker's parameter YAML (the one parameter table: names, types, bounds, rules).
#include <dvs_line_tracker/tracker_params.h>

#include "temp_file.h"

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  const std::string path = fuzz::writeTemp(data, size, ".yaml");
  dvs_line_tracker::LineTrackerParams params;
  try
  {
    dvs_line_tracker::loadTrackerParamsYaml(path, params);
    // Accepted parameters must be valid.
    if (!dvs_line_tracker::validateParams(params).empty())
      std::abort();
  }
  catch (const std::exception&)
  {
  }
  return 0;
}
