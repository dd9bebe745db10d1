#pragma once
// Prophesee EVT 2.0 word decoder (ROS-free, stateful, memory in / events out).
// 32-bit words, type = bits 31-28: 0x0 CD_OFF / 0x1 CD_ON (27-22 time LSBs, 21-11 x, 10-0 y),
// 0x8 TIME_HIGH (time bits 33-6), 0xA EXT_TRIGGER, 0xE OTHERS, 0xD IMU, 0xF CONTINUED.
// Nothing is emitted before the first TIME_HIGH; the 2^34 us wrap is unwrapped (vendor rule);
// x >= width or y >= height dropped; unknown words skipped and counted.
#include <dvs_driver/formats/event_format.h>

namespace dvs_driver
{
namespace formats
{
class Evt2Decoder
{
public:
  /// time_offset_us is added to every time (0 for sensor files).
  Evt2Decoder(uint32_t width = 0, uint32_t height = 0, int64_t time_offset_us = 0);

  /// Decode up to n_words 32-bit little-endian words into [p, end) (never past end). Sets
  /// words_used and returns the new p.
  Event* decode(const uint8_t* data, size_t n_words, Event* p, Event* end, size_t& words_used,
                ReaderStats& stats, std::vector<TriggerEvent>* triggers);

private:
  uint32_t width_, height_;
  bool have_th_ = false;
  int64_t th_us_ = 0;   // (wraps << 34) + (time high << 6), us
  int64_t wrap_us_ = 0;
  int64_t offset_us_ = 0;
};
}  // namespace formats
}  // namespace dvs_driver
