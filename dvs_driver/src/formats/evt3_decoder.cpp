#include <dvs_driver/formats/evt3_decoder.h>
#include <dvs_driver/formats/chunked_file.h>

#include <cstddef>
#include <cstring>

namespace dvs_driver
{
namespace formats
{
namespace
{
constexpr uint32_t kAddressLimit = 2048;  // 11-bit addresses

static_assert(sizeof(Event) == 16 && offsetof(Event, t_ns) == 0 && offsetof(Event, x) == 8 &&
                  offsetof(Event, y) == 10 && offsetof(Event, polarity) == 12,
              "Event layout assumed by putEvent");

/// Writes one event as two 8-byte stores; `xyp` = x | y << 16 | polarity << 32 (padding 0).
inline void putEvent(Event* p, int64_t t_ns, uint64_t xyp)
{
  std::memcpy(reinterpret_cast<char*>(p), &t_ns, 8);
  std::memcpy(reinterpret_cast<char*>(p) + 8, &xyp, 8);
}
constexpr size_t kMaxKeptTriggers = 1 << 20;
}  // namespace

Evt3Decoder::Evt3Decoder(uint32_t width, uint32_t height, int64_t time_offset_us)
  : width_(width ? width : kAddressLimit), height_(height ? height : kAddressLimit), offset_us_(time_offset_us)
{
}

int64_t Evt3Decoder::onTimeLow(uint16_t w, ReaderStats& stats)
{
  const uint32_t tl = w & 0xFFF;
  if (have_tl_ && tl < tl_)
    ++stats.time_backsteps;
  tl_ = tl;
  have_tl_ = true;
  t_ns_ = base_ns_ + int64_t(tl_) * 1000;
  return t_ns_;
}

int64_t Evt3Decoder::onTimeHigh(uint16_t w, ReaderStats& stats)
{
  const uint32_t th = w & 0xFFF;
  if (have_th_ && th < th_)
  {
    if (th_ - th >= 2048)
    {
      ++loop_;
      ++stats.time_wraps;
    }
    else
      ++stats.time_backsteps;
  }
  if (!have_th_ || th != th_)
    tl_ = 0;  // the vendor zeroes TIME_LOW when TIME_HIGH changes
  th_ = th;
  have_th_ = true;
  base_ns_ = (offset_us_ + ((loop_ << 24) | (int64_t(th_) << 12))) * 1000;
  t_ns_ = base_ns_ + int64_t(tl_) * 1000;
  return t_ns_;
}

Event* Evt3Decoder::decode(const uint8_t* data, size_t n_words, Event* p, Event* end, size_t& words_used,
                           ReaderStats& stats, std::vector<TriggerEvent>* triggers)
{
  // The hot state lives in locals (members could alias the event stores) and is written back
  // at the end; the rare time words go through member functions.
  size_t i = 0;
  int64_t t_ns = t_ns_;
  uint64_t y16 = uint64_t(y_) << 16;  // y, placed for putEvent
  bool time_ok = have_th_ && have_tl_;
  bool y_ok = y_ok_;
  uint32_t base_x = base_x_;
  bool vect_pol = vect_pol_, base_ok = base_ok_;
  const uint32_t width = width_, height = height_;

  uint64_t dropped = 0;  // CD events not emitted since time_ok last changed
  auto flushDropped = [&]() {
    (time_ok ? stats.out_of_range : stats.before_time) += dropped;
    dropped = 0;
  };

  while (i < n_words && p < end)
  {
    const uint32_t w = loadLE<uint16_t>(data + 2 * i);
    ++i;
    const uint32_t type = w >> 12;
    if (__builtin_expect((type & 0xD) == 0, 1))  // 0x0 ADDR_Y or 0x2 ADDR_X
    {
      // ADDR_Y and ADDR_X (~85 % of the words of a real recording) without branches: the
      // candidate event is always written and p advances only for a kept ADDR_X.
      const uint64_t a = w & 0x7FF;
      const uint64_t is_x = type >> 1;          // 1 for ADDR_X, 0 for ADDR_Y
      const uint64_t mx = 0 - is_x;             // all ones for ADDR_X
      y16 = (y16 & mx) | ((a << 16) & ~mx);
      const uint32_t in_h = a < height, in_w = a < width;
      y_ok = (uint32_t(y_ok) & uint32_t(is_x)) | (in_h & uint32_t(is_x ^ 1));
      const uint64_t keep = is_x & uint64_t(time_ok & y_ok) & in_w;
      putEvent(p, t_ns, y16 | a | (uint64_t(w & 0x800) << 21));
      p += keep;
      dropped += is_x & (keep ^ 1);
      continue;
    }
    switch (type)
    {
      case 0x1:  // Y address of non-CD events: CD words ignored until the next ADDR_Y
        y_ok = false;
        ++stats.other_words;
        break;
      case 0x3:  // VECT_BASE_X
        base_x = w & 0x7FF;
        vect_pol = (w & 0x800) != 0;
        base_ok = true;
        break;
      case 0x4:  // VECT_12
      case 0x5:  // VECT_8
      {
        const bool v12 = type == 0x4;
        uint32_t mask = v12 ? (w & 0xFFF) : (w & 0xFF);
        const uint32_t n = v12 ? 12 : 8;
        const bool ok = time_ok && y_ok && base_ok;
        if (ok && base_x + n <= width)
        {
          const uint64_t yp = y16 | (uint64_t(vect_pol) << 32) | base_x;
          while (mask)
          {
            putEvent(p++, t_ns, yp + __builtin_ctz(mask));
            mask &= mask - 1;
          }
        }
        else if (ok)
        {
          while (mask)
          {
            const uint32_t b = __builtin_ctz(mask);
            if (base_x + b < width)
              putEvent(p++, t_ns, y16 | (uint64_t(vect_pol) << 32) | (base_x + b));
            else
              ++dropped;
            mask &= mask - 1;
          }
        }
        else
          dropped += uint64_t(__builtin_popcount(mask));
        base_x += n;
        break;
      }
      case 0x6:  // EVT_TIME_LOW
        flushDropped();
        t_ns = onTimeLow(uint16_t(w), stats);
        time_ok = have_th_;
        break;
      case 0x8:  // EVT_TIME_HIGH
        flushDropped();
        t_ns = onTimeHigh(uint16_t(w), stats);
        time_ok = have_tl_;
        break;
      case 0xA:  // EXT_TRIGGER
        ++stats.triggers;
        if (triggers && time_ok && triggers->size() < kMaxKeptTriggers)
          triggers->push_back(TriggerEvent{t_ns, uint8_t((w >> 8) & 0xF), bool(w & 1)});
        break;
      case 0x7:  // CONTINUED_4
      case 0xE:  // OTHERS
      case 0xF:  // CONTINUED_12
        ++stats.other_words;
        break;
      default:
        ++stats.unknown_words;
        break;
    }
  }
  flushDropped();
  y_ = uint16_t(y16 >> 16);
  y_ok_ = y_ok;
  base_x_ = base_x;
  vect_pol_ = vect_pol;
  base_ok_ = base_ok;
  words_used = i;
  return p;
}
}  // namespace formats
}  // namespace dvs_driver
