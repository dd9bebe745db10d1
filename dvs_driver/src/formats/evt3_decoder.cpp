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

Event* Evt3Decoder::decode(const uint8_t* data, size_t n_words, Event* p, Event* end, size_t& words_used,
                           ReaderStats& stats, std::vector<TriggerEvent>* triggers)
{
  // All hot state lives in locals (members could alias the event stores) and is written back
  // at the end.
  size_t i = 0;
  bool have_th = have_th_, have_tl = have_tl_, have_y = have_y_, y_in_range = y_in_range_;
  uint32_t th = th_, tl = tl_;
  int64_t loop = loop_, base_ns = base_ns_, t_ns = t_ns_;
  uint16_t y = y_;
  bool cd_ok = cd_ok_;
  uint32_t base_x = base_x_;
  bool vect_pol = vect_pol_, base_ok = base_ok_;
  const uint32_t width = width_, height = height_;
  const int64_t offset_ns = offset_us_ * 1000;

  auto drop = [&](uint64_t n) {
    if (!(have_th && have_tl))
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
      case 0x0:  // EVT_ADDR_Y
        y = w & 0x7FF;
        have_y = true;
        y_in_range = y < height;
        cd_ok = have_th && have_tl && y_in_range;
        break;
      case 0x1:  // Y address of non-CD events: CD words ignored until the next ADDR_Y
        have_y = false;
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
        const uint32_t new_tl = w & 0xFFF;
        if (have_tl && new_tl < tl)
          ++stats.time_backsteps;
        tl = new_tl;
        have_tl = true;
        t_ns = base_ns + int64_t(tl) * 1000;
        cd_ok = have_th && have_y && y_in_range;
        break;
      }
      case 0x8:  // EVT_TIME_HIGH
      {
        const uint32_t new_th = w & 0xFFF;
        if (have_th && new_th < th)
        {
          if (th - new_th >= 2048)
          {
            ++loop;
            ++stats.time_wraps;
          }
          else
            ++stats.time_backsteps;
        }
        if (!have_th || new_th != th)
          tl = 0;  // the vendor zeroes TIME_LOW when TIME_HIGH changes
        th = new_th;
        have_th = true;
        base_ns = offset_ns + ((loop << 24) | (int64_t(th) << 12)) * 1000;
        t_ns = base_ns + int64_t(tl) * 1000;
        cd_ok = have_tl && have_y && y_in_range;
        break;
      }
      case 0xA:  // EXT_TRIGGER
        ++stats.triggers;
        if (triggers && have_th && have_tl && triggers->size() < kMaxKeptTriggers)
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
  have_th_ = have_th;
  have_tl_ = have_tl;
  have_y_ = have_y;
  y_in_range_ = y_in_range;
  th_ = th;
  tl_ = tl;
  loop_ = loop;
  base_ns_ = base_ns;
  t_ns_ = t_ns;
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
