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

void Evt3Decoder::updateTime()
{
  base_ns_ = (offset_us_ + ((loop_ << 24) | (int64_t(th_) << 12))) * 1000;
  t_ns_ = base_ns_ + int64_t(tl_) * 1000;
  cd_ok_ = have_th_ && have_tl_ && have_y_ && y_in_range_;
}

Event* Evt3Decoder::decode(const uint8_t* data, size_t n_words, Event* p, Event* end, size_t& words_used,
                           ReaderStats& stats, std::vector<TriggerEvent>* triggers)
{
  size_t i = 0;
  // Hot state in locals (the compiler cannot keep members in registers across the stores to p).
  int64_t t_ns = t_ns_;
  uint16_t y = y_;
  bool cd_ok = cd_ok_;
  uint32_t base_x = base_x_;
  bool vect_pol = vect_pol_;
  bool base_ok = base_ok_;
  const uint32_t width = width_;
  auto drop = [&](uint64_t n) {
    if (!(have_th_ && have_tl_))
      stats.before_time += n;
    else
      stats.out_of_range += n;  // no y yet, y out of range, x out of range
  };

  while (i < n_words && p < end)
  {
    const uint16_t w = loadLE<uint16_t>(data + 2 * i);
    ++i;
    switch (w >> 12)
    {
      case 0x0:  // EVT_ADDR_Y
        y = w & 0x7FF;
        have_y_ = true;
        y_in_range_ = y < height_;
        cd_ok = have_th_ && have_tl_ && y_in_range_;
        break;
      case 0x1:  // Y address of non-CD events: CD words ignored until the next ADDR_Y
        have_y_ = false;
        cd_ok = false;
        ++stats.other_words;
        break;
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
            drop(1);
          if (i == n_words || p >= end)
            break;
          v = loadLE<uint16_t>(data + 2 * i);
          if ((v >> 12) != 0x2)
            break;
          ++i;
        }
        break;
      }
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
              drop(1);
            mask &= mask - 1;
          }
        }
        else if (mask)
          drop(__builtin_popcount(mask));
        base_x += n;
        break;
      }
      case 0x6:  // EVT_TIME_LOW
      {
        const uint32_t tl = w & 0xFFF;
        if (have_tl_ && tl < tl_)
          ++stats.time_backsteps;
        tl_ = tl;
        have_tl_ = true;
        updateTime();
        t_ns = t_ns_;
        cd_ok = cd_ok_;
        break;
      }
      case 0x8:  // EVT_TIME_HIGH
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
          tl_ = 0;
        th_ = th;
        have_th_ = true;
        updateTime();
        t_ns = t_ns_;
        cd_ok = cd_ok_;
        break;
      }
      case 0xA:  // EXT_TRIGGER
        ++stats.triggers;
        if (triggers && have_th_ && have_tl_ && triggers->size() < kMaxKeptTriggers)
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
  cd_ok_ = cd_ok;
  base_x_ = base_x;
  vect_pol_ = vect_pol;
  base_ok_ = base_ok;
  words_used = i;
  return p;
}
}  // namespace formats
}  // namespace dvs_driver
