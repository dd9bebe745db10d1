#pragma once
// Decoder of the DVS128 USB event stream (ROS-free). See
// ../shared/reference/dvs128-usb-protocol.md: little-endian 4-byte words `b0 b1 b2 b3`,
// addr = b0 | b1 << 8, ts16 = b2 | b3 << 8; b3 & 0x80 = wrap (+16384 us), b3 & 0x40 = timestamp
// reset marker, else an event at offset + ts16 us; addr & 0x8000 = external sync input, else a
// pixel with x = 127 - ((addr >> 1) & 0x7F), y = 127 - ((addr >> 8) & 0x7F), ON when bit 0 is 0.
//
// The decoder is a template over the consumer so the per-event path inlines. A consumer is any
// type with these members (derive from Dvs128ConsumerBase to get no-op defaults):
//   void event(int64_t t_us, uint16_t x, uint16_t y, bool polarity);   // (0,0) = top-left
//   void sync(int64_t t_us);                                            // external input edge
//   void timestampReset();                                              // device time restarts at 0
//   void nonMonotonic(int64_t previous_us, int64_t t_us);               // warned, time clamped
#include <dvs_driver/event.h>

#include <cstddef>
#include <cstdint>

namespace dvs_driver
{
constexpr uint16_t kDvs128Width = 128;
constexpr uint16_t kDvs128Height = 128;

/// Pixel of a DVS128 address (also the AEDAT DVS128 address): flips x and y to a top-left origin.
/// Returns false for an external sync address (bit 15), leaving x, y, polarity untouched.
inline bool decodeDvs128Address(uint32_t addr, uint16_t& x, uint16_t& y, bool& polarity)
{
  if (addr & 0x8000u)
    return false;
  x = static_cast<uint16_t>(127u - ((addr >> 1) & 0x7Fu));
  y = static_cast<uint16_t>(127u - ((addr >> 8) & 0x7Fu));
  polarity = (addr & 1u) == 0;
  return true;
}

/// No-op defaults of the consumer interface.
struct Dvs128ConsumerBase
{
  void event(int64_t, uint16_t, uint16_t, bool) {}
  void sync(int64_t) {}
  void timestampReset() {}
  void nonMonotonic(int64_t, int64_t) {}
};

/// Running counts of what the decoder saw.
struct Dvs128DecoderStats
{
  uint64_t words = 0;          ///< complete 4-byte words decoded
  uint64_t events = 0;         ///< pixel events delivered
  uint64_t sync_events = 0;    ///< external sync events delivered
  uint64_t wraps = 0;          ///< wrap markers
  uint64_t resets = 0;         ///< timestamp reset markers
  uint64_t non_monotonic = 0;  ///< events whose time went backwards (delivered with the last time)
};

/// Stateful decoder: keeps the 64-bit time offset, the last time and up to 3 bytes of a word
/// split across transfers.
class Dvs128Decoder
{
public:
  /// Decode `size` bytes; an incomplete trailing word is kept and completed by the next call.
  template <class Consumer>
  void decode(const uint8_t* data, size_t size, Consumer& consumer);

  /// Forget the partial word, the offset and the last time (e.g. after a reconnect).
  void reset()
  {
    pending_size_ = 0;
    offset_us_ = 0;
    last_us_ = 0;
  }

  const Dvs128DecoderStats& stats() const { return stats_; }
  /// Bytes of an incomplete word waiting for the next transfer (0..3).
  size_t pendingBytes() const { return pending_size_; }
  /// Current wrap offset (us since the last reset, excluding the 16-bit part).
  int64_t offsetUs() const { return offset_us_; }

private:
  template <class Consumer>
  inline void word(uint8_t b0, uint8_t b1, uint8_t b2, uint8_t b3, Consumer& consumer);

  uint8_t pending_[4] = {0, 0, 0, 0};
  size_t pending_size_ = 0;
  int64_t offset_us_ = 0;
  int64_t last_us_ = 0;
  Dvs128DecoderStats stats_;
};

template <class Consumer>
inline void Dvs128Decoder::word(uint8_t b0, uint8_t b1, uint8_t b2, uint8_t b3, Consumer& consumer)
{
  ++stats_.words;
  if (b3 & 0x80u)
  {
    offset_us_ += 0x4000;
    ++stats_.wraps;
    return;
  }
  if (b3 & 0x40u)
  {
    offset_us_ = 0;
    last_us_ = 0;
    ++stats_.resets;
    consumer.timestampReset();
    return;
  }
  const uint32_t addr = static_cast<uint32_t>(b0) | (static_cast<uint32_t>(b1) << 8);
  int64_t t_us = offset_us_ + (static_cast<uint32_t>(b2) | (static_cast<uint32_t>(b3) << 8));
  if (t_us < last_us_)
  {
    ++stats_.non_monotonic;
    consumer.nonMonotonic(last_us_, t_us);
    t_us = last_us_;
  }
  last_us_ = t_us;
  uint16_t x, y;
  bool polarity;
  if (decodeDvs128Address(addr, x, y, polarity))
  {
    ++stats_.events;
    consumer.event(t_us, x, y, polarity);
  }
  else
  {
    ++stats_.sync_events;
    consumer.sync(t_us);
  }
}

template <class Consumer>
void Dvs128Decoder::decode(const uint8_t* data, size_t size, Consumer& consumer)
{
  if (pending_size_ > 0)
  {
    while (pending_size_ < 4 && size > 0)
    {
      pending_[pending_size_++] = *data++;
      --size;
    }
    if (pending_size_ < 4)
      return;
    word(pending_[0], pending_[1], pending_[2], pending_[3], consumer);
    pending_size_ = 0;
  }
  const uint8_t* end = data + (size & ~size_t(3));
  for (const uint8_t* p = data; p != end; p += 4)
    word(p[0], p[1], p[2], p[3], consumer);
  for (const uint8_t* p = end; p != data + size; ++p)
    pending_[pending_size_++] = *p;
}

/// Consumer that appends pixel events (device time, t_ns = t_us * 1000) to a vector; sync
/// events and resets are counted only.
struct Dvs128EventCollector : Dvs128ConsumerBase
{
  explicit Dvs128EventCollector(EventVector& out) : events(out) {}
  void event(int64_t t_us, uint16_t x, uint16_t y, bool polarity)
  {
    events.push_back(Event{t_us * 1000, x, y, polarity});
  }
  EventVector& events;
};
}  // namespace dvs_driver
