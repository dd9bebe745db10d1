// AEDAT 2.0 reader (header lines, big-endian address/time records, sensor detection).
#include <dvs_driver/aedat_reader.h>

#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  try
  {
    dvs_driver::readAedat(data, size, "fuzz.aedat");
  }
  catch (const std::exception&)
  {
  }
  return 0;
}
