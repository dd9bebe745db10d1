// AEDAT 3.1 reader and writer: layout in ../shared/reference/event-formats.md section 1.
#include <dvs_driver/formats/aedat3.h>
#include <dvs_driver/formats/batched_reader.h>
#include <dvs_driver/formats/chunked_file.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace dvs_driver
{
namespace formats
{
namespace
{
constexpr size_t kPacketHeader = 28;
constexpr int16_t kPolarity = 1;

struct DeviceSize
{
  const char* prefix;
  uint32_t width, height;
};
// Longest prefixes first.
constexpr DeviceSize kDevices[] = {{"DAVIS346", 346, 260}, {"DAVIS240", 240, 180}, {"DAVIS208", 208, 192},
                                   {"DAVIS128", 128, 128}, {"DAVIS640", 640, 480}, {"DVS128", 128, 128}};
}  // namespace

bool aedat3SourceSize(const std::string& device, uint32_t& width, uint32_t& height)
{
  for (const auto& d : kDevices)
    if (device.compare(0, std::strlen(d.prefix), d.prefix) == 0)
    {
      width = d.width;
      height = d.height;
      return true;
    }
  return false;
}

namespace
{
class Aedat3Reader : public BatchedReader
{
public:
  explicit Aedat3Reader(const std::string& path) : file_(path)
  {
    stats_.file_size = file_.size();
    file_.refill();
    const char* b = reinterpret_cast<const char*>(file_.begin());
    const size_t n = file_.available();
    size_t pos = 0;
    bool ended = false, raw = false;
    std::string version, format;
    while (pos < n && b[pos] == '#')
    {
      const char* eol = static_cast<const char*>(std::memchr(b + pos, '\n', n - pos));
      if (!eol)
        break;
      std::string line(b + pos, size_t(eol - (b + pos)));
      pos = size_t(eol - b) + 1;
      if (!line.empty() && line.back() == '\r')
        line.pop_back();
      if (line.compare(0, 10, "#!AER-DAT3") == 0)
        version = line.substr(9);
      else if (line.compare(0, 9, "#Format: ") == 0)
      {
        format = line.substr(9);
        raw = format == "RAW";
      }
      else if (line.compare(0, 8, "#Source ") == 0 && width_ == 0)
      {
        const size_t colon = line.find(": ");
        if (colon != std::string::npos)
        {
          device_ = line.substr(colon + 2);
          aedat3SourceSize(device_, width_, height_);
        }
      }
      else if (line == "#!END-HEADER")
      {
        ended = true;
        break;
      }
    }
    if (version.empty())
      throw EventFormatError(path + ": not an AEDAT 3 file (no #!AER-DAT3 line)");
    if (version != "3.1")
      throw EventFormatError(path + ": AEDAT version '" + version + "' is not supported (3.1 is)");
    if (!raw)
      throw EventFormatError(path + ": AEDAT 3.1 format '" + format + "' is not supported (RAW is)");
    if (!ended)
      throw EventFormatError(path + ": AEDAT 3.1 header has no #!END-HEADER line");
    file_.consume(pos);
    if (width_ == 0)
      warn("size: the AEDAT 3.1 source '" + device_ + "' is not a known device; the sensor size is unknown");
    limit_x_ = width_ ? width_ : 0x8000;
    limit_y_ = height_ ? height_ : 0x8000;
  }
  uint32_t width() const override { return width_; }
  uint32_t height() const override { return height_; }
  std::string formatName() const override { return "AEDAT 3.1" + (device_.empty() ? "" : " (" + device_ + ")"); }

protected:
  Event* decode(Event* p, Event* end) override
  {
    for (;;)
    {
      if (events_left_ > 0)
      {
        const size_t n = std::min<size_t>({events_left_, file_.available() / 8, size_t(end - p)});
        const uint8_t* q = file_.begin();
        for (size_t k = 0; k < n; ++k, q += 8)
        {
          const uint32_t d = loadLE<uint32_t>(q);
          const int32_t ts = loadLE<int32_t>(q + 4);
          const uint16_t x = (d >> 17) & 0x7FFF, y = (d >> 2) & 0x7FFF;
          if (!(d & 1))
            ++stats_.invalid_events;
          else if (x < limit_x_ && y < limit_y_)
            *p++ = Event{(overflow_ | int64_t(ts)) * 1000, x, y, bool(d & 2)};
          else
            ++stats_.out_of_range;
        }
        file_.consume(8 * n);
        events_left_ -= n;
        stats_.bytes_read = file_.offset();
        if (p >= end)
          return p;
        if (events_left_ == 0 || file_.available() >= 8)
          continue;
      }
      else if (skip_left_ > 0)
      {
        const size_t n = std::min<uint64_t>(skip_left_, file_.available());
        file_.consume(n);
        skip_left_ -= n;
        stats_.bytes_read = file_.offset();
        if (skip_left_ == 0)
          continue;
      }
      else if (file_.available() >= kPacketHeader)
      {
        startPacket();
        continue;
      }
      // Need more bytes.
      if (!file_.refill())
      {
        if (file_.available() > 0 || events_left_ > 0 || skip_left_ > 0)
        {
          stats_.truncated = true;
          // the partial event, the packet whose body is cut, or the partial packet header
          stats_.truncated_offset = events_left_ == 0 && skip_left_ > 0 ? packet_at_ : file_.offset();
          stats_.truncated_bytes = file_.size() - stats_.truncated_offset;
          warn("truncated: the AEDAT 3.1 file ends inside a packet; the incomplete data starts at byte " +
               std::to_string(stats_.truncated_offset));
          events_left_ = skip_left_ = 0;
        }
        stats_.bytes_read = file_.offset() + file_.available();
        return p;
      }
    }
  }

private:
  void startPacket()
  {
    const uint8_t* h = file_.begin();
    const int16_t type = loadLE<int16_t>(h);
    const int32_t size = loadLE<int32_t>(h + 4), ts_offset = loadLE<int32_t>(h + 8);
    const int32_t overflow = loadLE<int32_t>(h + 12), capacity = loadLE<int32_t>(h + 16);
    const int32_t number = loadLE<int32_t>(h + 20);
    const uint64_t header_at = file_.offset();
    packet_at_ = header_at;
    file_.consume(kPacketHeader);
    if (size <= 0 || capacity < 0 || number < 0 || number > capacity || overflow < 0)
    {
      // Nothing after a malformed header can be trusted: stop here.
      ++stats_.damaged_packets;
      warn("damaged: malformed AEDAT 3.1 packet header at byte " + std::to_string(header_at) +
           "; the rest of the file is ignored");
      skip_left_ = file_.size() - file_.offset();
      return;
    }
    if (type == kPolarity && size == 8 && ts_offset == 4)
    {
      events_left_ = uint64_t(number);
      skip_after_ = uint64_t(capacity - number) * 8;
      overflow_ = int64_t(overflow) << 31;
      if (skip_after_ > 0)
        skip_left_ = skip_after_;
      return;
    }
    if (type >= 0 && type <= 12)
      ++stats_.other_words;
    else
    {
      ++stats_.unknown_words;
      warn("unknown-packet: AEDAT 3.1 packets of unknown types are skipped (first: type " + std::to_string(type) +
           " at byte " + std::to_string(header_at) + ")");
    }
    skip_left_ = uint64_t(capacity) * uint64_t(size);
  }

  ChunkedFile file_;
  std::string device_;
  uint32_t width_ = 0, height_ = 0, limit_x_ = 0, limit_y_ = 0;
  uint64_t events_left_ = 0, skip_left_ = 0, skip_after_ = 0, packet_at_ = 0;
  int64_t overflow_ = 0;
};
}  // namespace

std::unique_ptr<EventFileReader> openAedat3(const std::string& path)
{
  return std::make_unique<Aedat3Reader>(path);
}

Aedat3Writer::Aedat3Writer(const std::string& path, const std::string& device, size_t events_per_packet)
  : path_(path), per_packet_(events_per_packet ? events_per_packet : 4096)
{
  f_ = std::fopen(path.c_str(), "wb");
  if (!f_)
    throw EventFormatError(path + ": cannot create (" + std::strerror(errno) + ")");
  const std::string h = "#!AER-DAT3.1\r\n#Format: RAW\r\n#Source 1: " + device +
                        "\r\n#Start-Time: 1970-01-01 00:00:00 (TZ+0000)\r\n#!END-HEADER\r\n";
  if (std::fwrite(h.data(), 1, h.size(), f_) != h.size())
    throw EventFormatError(path + ": write failed");
}

Aedat3Writer::~Aedat3Writer()
{
  try
  {
    close();
  }
  catch (...)
  {
  }
}

void Aedat3Writer::write(const Event* events, size_t n)
{
  if (!f_)
    throw EventFormatError(path_ + ": write after close");
  for (size_t k = 0; k < n; ++k)
  {
    const Event& e = events[k];
    const int64_t t_us = e.t_ns >= 0 ? e.t_ns / 1000 : -1;
    if (t_us < 0 || (t_us >> 31) > INT32_MAX)
      throw EventFormatError(path_ + ": AEDAT 3.1 cannot store time " + std::to_string(e.t_ns) + " ns");
    if (e.x > 0x7FFF || e.y > 0x7FFF)
      throw EventFormatError(path_ + ": AEDAT 3.1 cannot store pixel (" + std::to_string(e.x) + ", " +
                             std::to_string(e.y) + ")");
    const int32_t overflow = int32_t(t_us >> 31);
    if (overflow != overflow_ || words_.size() / 2 >= per_packet_)
    {
      flushPacket();
      overflow_ = overflow;
    }
    words_.push_back(uint32_t(e.x) << 17 | uint32_t(e.y) << 2 | (e.polarity ? 2u : 0u) | 1u);
    words_.push_back(uint32_t(t_us & 0x7FFFFFFF));
  }
}

void Aedat3Writer::flushPacket()
{
  if (words_.empty())
    return;
  const int32_t n = int32_t(words_.size() / 2);
  int32_t h32[7] = {0, 8, 4, overflow_, n, n, n};
  uint8_t h[kPacketHeader];
  std::memcpy(h, h32, sizeof h);
  const int16_t type = kPolarity, source = 1;
  std::memcpy(h, &type, 2);
  std::memcpy(h + 2, &source, 2);
  if (std::fwrite(h, 1, sizeof h, f_) != sizeof h ||
      std::fwrite(words_.data(), 4, words_.size(), f_) != words_.size())
    throw EventFormatError(path_ + ": write failed (" + std::strerror(errno) + ")");
  words_.clear();
}

void Aedat3Writer::close()
{
  if (!f_)
    return;
  flushPacket();
  const bool ok = std::fclose(f_) == 0;
  f_ = nullptr;
  if (!ok)
    throw EventFormatError(path_ + ": closing failed");
}
}  // namespace formats
}  // namespace dvs_driver
