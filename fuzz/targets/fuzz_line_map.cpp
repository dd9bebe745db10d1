// Line map YAML (segments, up, frame_id; polygon assembly and planarity).
#include <dvs_line_tracker/line_map.h>

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  try
  {
    dvs_line_tracker::parseLineMap(std::string(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
  }
  catch (const std::exception&)
  {
  }
  return 0;
}
