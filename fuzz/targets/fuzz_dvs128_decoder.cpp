// DVS128 USB packet decoder: arbitrary bytes split into transfers of arbitrary sizes.
#include <dvs_driver/dvs128_decoder.h>

#include <cstdlib>

namespace
{
struct Checked : dvs_driver::Dvs128ConsumerBase
{
  int64_t last = -1;
  void event(int64_t t_us, uint16_t x, uint16_t y, bool)
  {
    // Invariants the driver relies on: pixels inside the 128x128 array, time never decreasing.
    if (x >= 128 || y >= 128 || t_us < last)
      std::abort();
    last = t_us;
  }
  void timestampReset() { last = -1; }
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  if (size < 1)
    return 0;
  dvs_driver::Dvs128Decoder decoder;
  Checked consumer;
  // The first byte chooses the transfer size: words may straddle transfers.
  const size_t chunk = 1 + data[0] % 64;
  for (size_t i = 1; i < size; i += chunk)
    decoder.decode(data + i, std::min(chunk, size - i), consumer);
  return 0;
}
