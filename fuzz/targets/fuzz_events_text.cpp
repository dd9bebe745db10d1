// events.txt parser (Event Camera Dataset text: `t x y p` per line).
#include <dvs_driver/event_text_io.h>

#include <sstream>
#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try
  {
    dvs_driver::readEventsText(in, "fuzz.txt");
  }
  catch (const std::exception&)
  {
    // A named error is the expected outcome for malformed input; crashes and UB are findings.
  }
  return 0;
}
