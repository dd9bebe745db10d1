// EVT 3.0 RAW writer: one TIME_HIGH / TIME_LOW / ADDR_Y word when they change, one ADDR_X word
// per event (no vectors). TIME_HIGH advances in steps of at most 2047 so that every 2^24 us wrap
// shows as a fall of >= 2048, which is what the readers count as a wrap.
#include <dvs_driver/formats/prophesee_raw.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace dvs_driver
{
namespace formats
{
namespace
{
constexpr int64_t kOffsetThresholdUs = int64_t(1) << 32;
}

Evt3Writer::Evt3Writer(const std::string& path, uint32_t width, uint32_t height)
  : path_(path), width_(width), height_(height)
{
  if (width == 0 || height == 0 || width > 2048 || height > 2048)
    throw EventFormatError(path + ": EVT 3.0 cannot store a " + std::to_string(width) + "x" + std::to_string(height) +
                           " sensor (1..2048 each way)");
  f_ = std::fopen(path.c_str(), "wb");
  if (!f_)
    throw EventFormatError(path + ": cannot create (" + std::strerror(errno) + ")");
  words_.reserve(1 << 16);
}

Evt3Writer::~Evt3Writer()
{
  try
  {
    close();
  }
  catch (...)
  {
  }
}

void Evt3Writer::start(int64_t first_us)
{
  if (first_us >= kOffsetThresholdUs)
    offset_us_ = first_us - first_us % 1000000;
  std::string h = "% evt 3.0\n% format EVT3;height=" + std::to_string(height_) + ";width=" + std::to_string(width_) +
                  "\n% geometry " + std::to_string(width_) + "x" + std::to_string(height_) + "\n";
  if (offset_us_ != 0)
    h += "% dvs_time_offset_us " + std::to_string(offset_us_) + "\n";
  h += "% end\n";
  if (std::fwrite(h.data(), 1, h.size(), f_) != h.size())
    throw EventFormatError(path_ + ": write failed");
  started_ = true;
}

void Evt3Writer::flush()
{
  if (!words_.empty() && std::fwrite(words_.data(), 2, words_.size(), f_) != words_.size())
    throw EventFormatError(path_ + ": write failed (" + std::strerror(errno) + ")");
  words_.clear();
}

void Evt3Writer::write(const Event* ev, size_t n)
{
  if (!f_)
    throw EventFormatError(path_ + ": write after close");
  for (size_t k = 0; k < n; ++k, ++written_)
  {
    const Event& e = ev[k];
    // floor(t_ns / 1000)
    const int64_t t_us = e.t_ns >= 0 ? e.t_ns / 1000 : -((-e.t_ns + 999) / 1000);
    if (!started_)
      start(t_us);
    const int64_t r = t_us - offset_us_;
    if (r < 0)
      throw EventFormatError(path_ + ": EVT 3.0 cannot store event " + std::to_string(written_) + " at t = " +
                             std::to_string(t_us) + " us (before the time origin " + std::to_string(offset_us_) +
                             " us)");
    if (e.x >= width_ || e.y >= height_)
      throw EventFormatError(path_ + ": event " + std::to_string(written_) + " at (" + std::to_string(e.x) + ", " +
                             std::to_string(e.y) + ") lies outside the " + std::to_string(width_) + "x" +
                             std::to_string(height_) + " sensor");
    const int64_t total = r >> 12;
    if (total != total_th_)
    {
      if (total_th_ < 0)
      {
        words_.push_back(0x8000);  // TIME_HIGH 0 starts the stream
        total_th_ = 0;
      }
      if (total > total_th_)
      {
        while (total_th_ != total)
        {
          total_th_ += std::min<int64_t>(total - total_th_, 2047);
          words_.push_back(uint16_t(0x8000 | (total_th_ & 0xFFF)));
        }
      }
      else if (total < total_th_)
      {
        // A small back step within one 2^24 us loop is taken as it is by the readers.
        if ((total >> 12) != (total_th_ >> 12) || total_th_ - total >= 2048)
          throw EventFormatError(path_ + ": EVT 3.0 cannot store event " + std::to_string(written_) +
                                 ": its time goes back too far (" + std::to_string(t_us) + " us)");
        total_th_ = total;
        words_.push_back(uint16_t(0x8000 | (total & 0xFFF)));
      }
      tl_ = -1;  // readers zero TIME_LOW when TIME_HIGH changes
    }
    const int32_t tl = int32_t(r & 0xFFF);
    if (tl != tl_)
    {
      words_.push_back(uint16_t(0x6000 | tl));
      tl_ = tl;
    }
    if (e.y != y_)
    {
      words_.push_back(uint16_t(0x0000 | e.y));
      y_ = e.y;
    }
    words_.push_back(uint16_t(0x2000 | (e.polarity ? 0x800 : 0) | e.x));
    if (words_.size() >= (1 << 16) - 8)
      flush();
  }
}

void Evt3Writer::close()
{
  if (!f_)
    return;
  if (!started_)
    start(0);
  flush();
  const bool ok = std::fclose(f_) == 0;
  f_ = nullptr;
  if (!ok)
    throw EventFormatError(path_ + ": closing failed");
}
}  // namespace formats
}  // namespace dvs_driver
