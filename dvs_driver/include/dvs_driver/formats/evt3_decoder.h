#pragma once
// Prophesee EVT 3.0 word decoder (ROS-free, stateful, memory in / events out). The state carries
// across calls, so a stream may be fed in arbitrary pieces (file chunks, EventPacket messages).
// Rules (../shared/reference/event-formats.md section 3): nothing is emitted before a TIME_HIGH
// and a TIME_LOW; no CD event before an ADDR_Y; x >= width or y >= height dropped; TIME_LOW
// steps back are taken as they are (the vendor's behaviour); TIME_HIGH falling by >= 2048
// counts a 2^24 us wrap; TIME_LOW is zeroed when TIME_HIGH changes; unknown words skipped and
// counted; vectors without a VECT_BASE_X dropped.
#include <dvs_driver/formats/event_format.h>

namespace dvs_driver
{
namespace formats
{
class Evt3Decoder
{
public:
  /// width/height 0 = unknown (only the 11-bit address limit applies). time_offset_us is added
  /// to every time (0 for sensor files; see Evt3Writer).
  Evt3Decoder(uint32_t width = 0, uint32_t height = 0, int64_t time_offset_us = 0);

  /// Maximum events one word can produce (the decoder may write this many past `end`).
  static constexpr size_t kMaxEventsPerWord = 12;

  /// Decode up to n_words 16-bit little-endian words from `data` into [p, end). Stops after the
  /// word that reaches end (up to kMaxEventsPerWord - 1 events past end). Sets words_used and
  /// returns the new p. Triggers go to `triggers` (if not null), counts to `stats`.
  Event* decode(const uint8_t* data, size_t n_words, Event* p, Event* end, size_t& words_used,
                ReaderStats& stats, std::vector<TriggerEvent>* triggers);

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }

private:
  int64_t onTimeLow(uint16_t w, ReaderStats& stats);
  int64_t onTimeHigh(uint16_t w, ReaderStats& stats);

  uint32_t width_, height_;
  // time
  bool have_th_ = false, have_tl_ = false;
  uint32_t th_ = 0, tl_ = 0;
  int64_t loop_ = 0;
  int64_t offset_us_ = 0;
  int64_t base_ns_ = 0;  // (offset + (loop << 24 | th << 12)) us in ns
  int64_t t_ns_ = 0;
  // address
  bool y_ok_ = false;  // an ADDR_Y was seen and is inside the sensor
  uint16_t y_ = 0;
  bool base_ok_ = false;
  uint32_t base_x_ = 0;
  bool vect_pol_ = false;
};
}  // namespace formats
}  // namespace dvs_driver
