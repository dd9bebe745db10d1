#include <dvs_driver/formats/evt2_decoder.h>
#include <dvs_driver/formats/chunked_file.h>

namespace dvs_driver
{
namespace formats
{
namespace
{
constexpr uint32_t kAddressLimit = 2048;
constexpr int64_t kWrapUs = int64_t(1) << 34;
constexpr int64_t kWrapThresholdUs = kWrapUs - 64 - 10000;  // vendor rule
constexpr size_t kMaxKeptTriggers = 1 << 20;
}  // namespace

Evt2Decoder::Evt2Decoder(uint32_t width, uint32_t height, int64_t time_offset_us)
  : width_(width ? width : kAddressLimit), height_(height ? height : kAddressLimit), offset_us_(time_offset_us)
{
}

Event* Evt2Decoder::decode(const uint8_t* data, size_t n_words, Event* p, Event* end, size_t& words_used,
                           ReaderStats& stats, std::vector<TriggerEvent>* triggers)
{
  size_t i = 0;
  int64_t th_us = th_us_;
  const uint32_t width = width_, height = height_;
  while (i < n_words && p < end)
  {
    const uint32_t w = loadLE<uint32_t>(data + 4 * i);
    ++i;
    switch (w >> 28)
    {
      case 0x0:
      case 0x1:
      {
        const uint16_t x = (w >> 11) & 0x7FF, y = w & 0x7FF;
        if (!have_th_)
          ++stats.before_time;
        else if (x < width && y < height)
          *p++ = Event{(offset_us_ + (th_us | ((w >> 22) & 0x3F))) * 1000, x, y, bool(w >> 28)};
        else
          ++stats.out_of_range;
        break;
      }
      case 0x8:
      {
        int64_t t = wrap_us_ + (int64_t(w & 0x0FFFFFFF) << 6);
        if (have_th_ && t < th_us && th_us - t >= kWrapThresholdUs)
        {
          wrap_us_ += kWrapUs;
          t += kWrapUs;
          ++stats.time_wraps;
        }
        else if (have_th_ && t < th_us)
          ++stats.time_backsteps;
        th_us = t;
        have_th_ = true;
        break;
      }
      case 0xA:
        ++stats.triggers;
        if (triggers && have_th_ && triggers->size() < kMaxKeptTriggers)
          triggers->push_back(
              TriggerEvent{(offset_us_ + (th_us | ((w >> 22) & 0x3F))) * 1000, uint8_t((w >> 8) & 0x1F), bool(w & 1)});
        break;
      case 0xD:  // IMU
      case 0xE:  // OTHERS
      case 0xF:  // CONTINUED
        ++stats.other_words;
        break;
      default:
        ++stats.unknown_words;
        break;
    }
  }
  th_us_ = th_us;
  words_used = i;
  return p;
}
}  // namespace formats
}  // namespace dvs_driver
