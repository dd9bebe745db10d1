#include <dvs_driver/formats/batched_reader.h>
#include <dvs_driver/formats/chunked_file.h>
#include <dvs_driver/formats/evt2_decoder.h>
#include <dvs_driver/formats/evt3_decoder.h>
#include <dvs_driver/formats/prophesee_raw.h>

#include <cerrno>
#include <cstdlib>
#include <sstream>

namespace dvs_driver
{
namespace formats
{
namespace
{
bool parseSize(const std::string& s, uint32_t& w, uint32_t& h)
{
  unsigned long a = 0, b = 0;
  char x = 0;
  std::istringstream in(s);
  if (in >> a >> x >> b && (x == 'x' || x == 'X') && a > 0 && b > 0 && a <= 65536 && b <= 65536)
  {
    w = uint32_t(a);
    h = uint32_t(b);
    return true;
  }
  return false;
}

std::string trim(const std::string& s)
{
  size_t a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}
}  // namespace

bool rawSystemIdSize(long id, uint32_t& width, uint32_t& height)
{
  switch (id)
  {
    case 21:  // Gen3.0 (CCAM3)
      width = 640;
      height = 480;
      return true;
    case 48:  // EVK3 Gen4.1
    case 0x31:  // IMX636 EVK3
    case 0x32:  // IMX636 EVK2
      width = 1280;
      height = 720;
      return true;
    default:
      return false;
  }
}

RawHeader parseRawHeader(const uint8_t* data, size_t size, const std::string& name)
{
  RawHeader h;
  size_t pos = 0;
  while (pos + 1 < size && data[pos] == '%' && data[pos + 1] == ' ')
  {
    size_t eol = pos;
    while (eol < size && data[eol] != '\n')
      ++eol;
    if (eol == size)
      throw EventFormatError(name + ": Prophesee RAW header line without an end at byte " + std::to_string(pos));
    std::string line(reinterpret_cast<const char*>(data + pos + 2), eol - pos - 2);
    pos = eol + 1;
    line = trim(line);
    if (line == "end")
      break;
    const size_t sp = line.find(' ');
    h.keys[line.substr(0, sp)] = sp == std::string::npos ? "" : trim(line.substr(sp + 1));
  }
  h.data_offset = pos;

  // Version: `format EVT3;height=720;width=1280` or legacy `evt 3.0`.
  std::string version;
  auto f = h.keys.find("format");
  if (f != h.keys.end())
  {
    std::string fmt = f->second;
    version = fmt.substr(0, fmt.find(';'));
    size_t p = 0;
    uint32_t w = 0, hh = 0;
    while ((p = fmt.find(';', p)) != std::string::npos)
    {
      ++p;
      const size_t e = fmt.find(';', p);
      const std::string kv = fmt.substr(p, e == std::string::npos ? std::string::npos : e - p);
      if (kv.compare(0, 6, "width=") == 0)
        w = uint32_t(std::strtoul(kv.c_str() + 6, nullptr, 10));
      else if (kv.compare(0, 7, "height=") == 0)
        hh = uint32_t(std::strtoul(kv.c_str() + 7, nullptr, 10));
    }
    if (w > 0 && hh > 0)
    {
      h.width = w;
      h.height = hh;
      h.size_source = "format";
    }
  }
  else if ((f = h.keys.find("evt")) != h.keys.end())
    version = f->second;
  if (version == "EVT3" || version == "3.0" || version == "3")
    h.evt = 3;
  else if (version == "EVT2" || version == "2.0" || version == "2")
    h.evt = 2;
  else if (version.empty())
    throw EventFormatError(name + ": Prophesee RAW header names no event format (no `% format` or `% evt` line)");
  else
    throw EventFormatError(name + ": Prophesee RAW event format '" + version +
                           "' is not supported (EVT 2.0 and EVT 3.0 are)");
  auto o = h.keys.find("dvs_time_offset_us");
  if (o != h.keys.end())
  {
    // Our writer's offset for times beyond 2^32 us (Unix-epoch times): at most ~100 years, so
    // that offset + sensor time stays far from overflowing int64 nanoseconds.
    char* end = nullptr;
    errno = 0;
    h.time_offset_us = std::strtoll(o->second.c_str(), &end, 10);
    if (errno != 0 || end == o->second.c_str() || h.time_offset_us < 0 || h.time_offset_us > 4000000000000000LL)
      throw EventFormatError(name + ": header key dvs_time_offset_us '" + o->second +
                             "' is not a time offset in [0, 4e15] us");
  }
  auto e = h.keys.find("endianness");
  if (e != h.keys.end() && e->second != "little")
    throw EventFormatError(name + ": Prophesee RAW endianness '" + e->second + "' is not supported (little is)");

  if (h.size_source.empty())
  {
    auto g = h.keys.find("geometry");
    if (g != h.keys.end() && parseSize(g->second, h.width, h.height))
      h.size_source = "geometry";
  }
  if (h.size_source.empty())
  {
    auto s = h.keys.find("system_ID");
    if (s != h.keys.end())
    {
      char* endp = nullptr;
      const long id = std::strtol(s->second.c_str(), &endp, 0);
      if (endp != s->second.c_str() && rawSystemIdSize(id, h.width, h.height))
        h.size_source = "system_ID " + s->second;
    }
  }
  return h;
}

namespace
{
template <typename Decoder, size_t kWordBytes>
class RawReader : public BatchedReader
{
public:
  RawReader(std::unique_ptr<ChunkedFile> file, const RawHeader& header)
    : file_(std::move(file)), header_(header), decoder_(header.width, header.height, header.time_offset_us)
  {
    stats_.file_size = file_->size();
    file_->consume(header.data_offset);
    if (header.size_source.empty())
      warn("size: the RAW header gives no sensor size (no format/geometry/known system_ID)");
  }
  uint32_t width() const override { return header_.width; }
  uint32_t height() const override { return header_.height; }
  std::string formatName() const override
  {
    return kWordBytes == 2 ? "Prophesee RAW EVT 3.0" : "Prophesee RAW EVT 2.0";
  }

protected:
  Event* decode(Event* p, Event* end) override
  {
    for (;;)
    {
      size_t used = 0;
      p = decoder_.decode(file_->begin(), file_->available() / kWordBytes, p, end, used, stats_, &triggers_);
      file_->consume(used * kWordBytes);
      stats_.bytes_read = file_->offset();
      if (p >= end)
        return p;
      if (!file_->refill())
      {
        if (file_->available() > 0 && !stats_.truncated)
        {
          stats_.truncated = true;
          stats_.truncated_offset = file_->offset();
          stats_.truncated_bytes = file_->available();
          warn("truncated: the file ends inside a " + std::to_string(kWordBytes) + "-byte word at byte " +
               std::to_string(file_->offset()) + " (" + std::to_string(file_->available()) + " bytes ignored)");
        }
        return p;
      }
    }
  }

private:
  std::unique_ptr<ChunkedFile> file_;
  RawHeader header_;
  Decoder decoder_;
};
}  // namespace

std::unique_ptr<EventFileReader> openPropheseeRaw(const std::string& path)
{
  auto file = std::make_unique<ChunkedFile>(path);
  // The header must fit in the first chunk(s): read until a non-header line starts.
  file->refill();
  RawHeader h = parseRawHeader(file->begin(), file->available(), path);
  if (h.evt == 3)
    return std::make_unique<RawReader<Evt3Decoder, 2>>(std::move(file), h);
  return std::make_unique<RawReader<Evt2Decoder, 4>>(std::move(file), h);
}
}  // namespace formats
}  // namespace dvs_driver
