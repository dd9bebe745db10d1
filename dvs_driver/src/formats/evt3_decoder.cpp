#include <dvs_driver/formats/evt3_decoder.h>
#include <dvs_driver/formats/chunked_file.h>

namespace dvs_driver
{
namespace formats
{
namespace
{
constexpr uint32_t kAddressLimit = 2048;  // 11-bit addresses
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
  uint16_t y = y_;
  bool time_ok = have_th_ && have_tl_;
  bool y_ok = y_ok_;
  bool cd_ok = time_ok && y_ok;
  uint32_t base_x = base_x_;
  bool vect_pol = vect_pol_, base_ok = base_ok_;
  const uint32_t width = width_, height = height_;

  while (i < n_words && p < end)
  {
    const uint16_t w = loadLE<uint16_t>(data + 2 * i);
    ++i;
    switch (w >> 12)
    {
      case 0x2:  // EVT_ADDR_X
      {
        // Runs of ADDR_X words are the common case: stay in this loop while they last.
        uint16_t v = w;
        for (;;)
        {
          const uint16_t x = v & 0x7FF;
          if (cd_ok && x < width)
            *p++ = Event{t_ns, x, y, bool(v & 0x800)};
          else
            ++(time_ok ? stats.out_of_range : stats.before_time);
          if (i == n_words || p >= end)
            break;
          v = loadLE<uint16_t>(data + 2 * i);
          if ((v >> 12) != 0x2)
            break;
          ++i;
        }
        break;
      }
      case 0x0:  // EVT_ADDR_Y
        y = w & 0x7FF;
        y_ok = y < height;
        cd_ok = time_ok && y_ok;
        break;
      case 0x1:  // Y address of non-CD events: CD words ignored until the next ADDR_Y
        y_ok = false;
        cd_ok = false;
        ++stats.other_words;
        break;
      case 0x3:  // VECT_BASE_X
        base_x = w & 0x7FF;
        vect_pol = w & 0x800;
        base_ok = true;
        break;
      case 0x4:  // VECT_12
      case 0x5:  // VECT_8
      {
        const bool v12 = (w >> 12) == 0x4;
        uint32_t mask = v12 ? (w & 0xFFF) : (w & 0xFF);
        const uint32_t n = v12 ? 12 : 8;
        if (cd_ok && base_ok && base_x + n <= width)
        {
          while (mask)
          {
            const uint32_t b = __builtin_ctz(mask);
            *p++ = Event{t_ns, uint16_t(base_x + b), y, vect_pol};
            mask &= mask - 1;
          }
        }
        else if (cd_ok && base_ok)
        {
          while (mask)
          {
            const uint32_t b = __builtin_ctz(mask);
            if (base_x + b < width)
              *p++ = Event{t_ns, uint16_t(base_x + b), y, vect_pol};
            else
              ++stats.out_of_range;
            mask &= mask - 1;
          }
        }
        else if (mask)
          (time_ok ? stats.out_of_range : stats.before_time) += uint64_t(__builtin_popcount(mask));
        base_x += n;
        break;
      }
      case 0x6:  // EVT_TIME_LOW
        t_ns = onTimeLow(w, stats);
        time_ok = have_th_;
        cd_ok = time_ok && y_ok;
        break;
      case 0x8:  // EVT_TIME_HIGH
        t_ns = onTimeHigh(w, stats);
        time_ok = have_tl_;
        cd_ok = time_ok && y_ok;
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
  y_ = y;
  y_ok_ = y_ok;
  base_x_ = base_x;
  vect_pol_ = vect_pol;
  base_ok_ = base_ok;
  words_used = i;
  return p;
}
}  // namespace formats
}  // namespace dvs_driver
