// AEDAT 4.0 writer: the IOHeader, EventPacket and FileDataTable flatbuffers are laid out by hand
// (offsets relative to each buffer's size prefix, 8-byte fields 8-byte aligned, as flatc does).
#include <dvs_driver/formats/aedat4.h>
#include <dvs_driver/formats/compression.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace dvs_driver
{
namespace formats
{
namespace
{
template <typename T>
void put(std::vector<uint8_t>& b, size_t pos, T v)
{
  if (b.size() < pos + sizeof(T))
    b.resize(pos + sizeof(T), 0);
  std::memcpy(b.data() + pos, &v, sizeof(T));
}

void padTo(std::vector<uint8_t>& b, size_t align)
{
  while (b.size() % align)
    b.push_back(0);
}

std::string xmlSafe(std::string s)
{
  for (char& c : s)
    if (c == '<' || c == '>' || c == '&' || c == '"' || c == '\'')
      c = '_';
  return s;
}

/// The IOHeader's compression key: the reader's names, with "NONE" spelled as DV spells it.
const char* compressionKey(Aedat4Compression c)
{
  return c == Aedat4Compression::None ? "NONE" : aedat4CompressionName(c);
}

constexpr size_t kMagicSize = 14;
}  // namespace

Aedat4Writer::Aedat4Writer(const std::string& path, uint32_t width, uint32_t height, const Aedat4WriterOptions& options)
  : path_(path), width_(width), height_(height), opt_(options)
{
  if (width == 0 || height == 0 || width > 32767 || height > 32767)
    throw EventFormatError(path + ": AEDAT 4.0 cannot store a " + std::to_string(width) + "x" +
                           std::to_string(height) + " sensor");
  if (opt_.events_per_packet == 0)
    opt_.events_per_packet = 10000;
  f_ = std::fopen(path.c_str(), "wb");
  if (!f_)
    throw EventFormatError(path + ": cannot create (" + std::strerror(errno) + ")");

  const std::string w = std::to_string(width), h = std::to_string(height);
  const std::string xml =
      "<dv version=\"2.0\">\n"
      "    <node name=\"outInfo\" path=\"/mainloop/Recorder/outInfo/\">\n"
      "        <node name=\"0\" path=\"/mainloop/Recorder/outInfo/0/\">\n"
      "            <attr key=\"compression\" type=\"string\">" +
      std::string(compressionKey(opt_.compression)) +
      "</attr>\n"
      "            <attr key=\"originalModuleName\" type=\"string\">dvs_driver</attr>\n"
      "            <attr key=\"originalOutputName\" type=\"string\">events</attr>\n"
      "            <attr key=\"typeDescription\" type=\"string\">Array of events (polarity ON/OFF).</attr>\n"
      "            <attr key=\"typeIdentifier\" type=\"string\">EVTS</attr>\n"
      "            <node name=\"info\" path=\"/mainloop/Recorder/outInfo/0/info/\">\n"
      "                <attr key=\"sizeX\" type=\"int\">" +
      w +
      "</attr>\n"
      "                <attr key=\"sizeY\" type=\"int\">" +
      h +
      "</attr>\n"
      "                <attr key=\"source\" type=\"string\">" +
      xmlSafe(opt_.source) +
      "</attr>\n"
      "                <attr key=\"tsOffset\" type=\"long\">0</attr>\n"
      "            </node>\n"
      "        </node>\n"
      "    </node>\n"
      "</dv>\n";

  // IOHeader, positions relative to the size prefix (written at file offset 14).
  std::vector<uint8_t> b;
  put<uint32_t>(b, 4, 24 - 4);  // root table at 24
  b.resize(12);
  std::memcpy(b.data() + 8, "IOHE", 4);
  put<uint16_t>(b, 12, 10);  // vtable: size, table size, fields 0..2
  put<uint16_t>(b, 14, 20);
  put<uint16_t>(b, 16, 4);   // compression int32 at table + 4
  put<uint16_t>(b, 18, 8);   // dataTablePosition int64 at table + 8 (prefix offset 32: aligned)
  put<uint16_t>(b, 20, 16);  // infoNode offset at table + 16
  put<int32_t>(b, 24, 24 - 12);
  put<int32_t>(b, 28, int32_t(opt_.compression));
  put<int64_t>(b, 32, -1);  // patched by close()
  put<uint32_t>(b, 40, 44 - 40);
  put<uint32_t>(b, 44, uint32_t(xml.size()));
  b.insert(b.end(), xml.begin(), xml.end());
  b.push_back(0);
  padTo(b, 8);
  put<uint32_t>(b, 0, uint32_t(b.size() - 4));
  table_pos_field_ = kMagicSize + 32;
  if (std::fwrite("#!AER-DAT4.0\r\n", 1, kMagicSize, f_) != kMagicSize ||
      std::fwrite(b.data(), 1, b.size(), f_) != b.size())
    throw EventFormatError(path + ": write failed");
  offset_ = kMagicSize + b.size();
  packet_.reserve(opt_.events_per_packet);
}

Aedat4Writer::~Aedat4Writer()
{
  try
  {
    close();
  }
  catch (...)
  {
  }
}

void Aedat4Writer::write(const EventVector& events)
{
  write(events.data(), events.size());
}

void Aedat4Writer::write(const Event* events, size_t n)
{
  if (!f_)
    throw EventFormatError(path_ + ": write after close");
  for (size_t k = 0; k < n; ++k)
  {
    if (events[k].x >= width_ || events[k].y >= height_)
      throw EventFormatError(path_ + ": event at (" + std::to_string(events[k].x) + ", " +
                             std::to_string(events[k].y) + ") lies outside the " + std::to_string(width_) + "x" +
                             std::to_string(height_) + " sensor");
    packet_.push_back(events[k]);
    if (packet_.size() == opt_.events_per_packet)
      flushPacket();
  }
}

void Aedat4Writer::writeCompressed(int32_t stream_id, const std::vector<uint8_t>& raw, bool with_header)
{
  const std::vector<uint8_t>* out = &raw;
  switch (opt_.compression)
  {
    case Aedat4Compression::None:
      break;
    case Aedat4Compression::Lz4:
      lz4Compress(raw.data(), raw.size(), compressed_, 0);
      out = &compressed_;
      break;
    case Aedat4Compression::Lz4High:
      lz4Compress(raw.data(), raw.size(), compressed_, 9);
      out = &compressed_;
      break;
    case Aedat4Compression::Zstd:
      zstdCompress(raw.data(), raw.size(), compressed_, 3);
      out = &compressed_;
      break;
    case Aedat4Compression::ZstdHigh:
      zstdCompress(raw.data(), raw.size(), compressed_, 12);
      out = &compressed_;
      break;
  }
  if (with_header)
  {
    int32_t h[2] = {stream_id, int32_t(out->size())};
    if (std::fwrite(h, 1, 8, f_) != 8)
      throw EventFormatError(path_ + ": write failed (" + std::strerror(errno) + ")");
    offset_ += 8;
  }
  if (std::fwrite(out->data(), 1, out->size(), f_) != out->size())
    throw EventFormatError(path_ + ": write failed (" + std::strerror(errno) + ")");
  offset_ += out->size();
}

void Aedat4Writer::flushPacket()
{
  if (packet_.empty())
    return;
  // EventPacket: [size][root=16][EVTS][vtable 6,8,4][pad][table: soffset 8, vector offset 4]
  // [count][16-byte events: int64 t, int16 x, int16 y, bool on, 3 padding]
  const size_t n = packet_.size();
  raw_.assign(32 + 16 * n, 0);
  put<uint32_t>(raw_, 0, uint32_t(raw_.size() - 4));
  put<uint32_t>(raw_, 4, 20 - 4);
  std::memcpy(raw_.data() + 8, "EVTS", 4);
  put<uint16_t>(raw_, 12, 6);
  put<uint16_t>(raw_, 14, 8);
  put<uint16_t>(raw_, 16, 4);
  put<int32_t>(raw_, 20, 20 - 12);
  put<uint32_t>(raw_, 24, 28 - 24);
  put<uint32_t>(raw_, 28, uint32_t(n));
  int64_t t_min = INT64_MAX, t_max = INT64_MIN;
  uint8_t* q = raw_.data() + 32;
  for (const Event& e : packet_)
  {
    const int64_t t_us = e.t_ns >= 0 ? e.t_ns / 1000 : -((-e.t_ns + 999) / 1000);
    t_min = std::min(t_min, t_us);
    t_max = std::max(t_max, t_us);
    const int16_t x = int16_t(e.x), y = int16_t(e.y);
    std::memcpy(q, &t_us, 8);
    std::memcpy(q + 8, &x, 2);
    std::memcpy(q + 10, &y, 2);
    q[12] = e.polarity ? 1 : 0;
    q += 16;
  }
  const uint64_t payload_offset = offset_ + 8;
  writeCompressed(0, raw_, true);
  table_.push_back(TableEntry{int64_t(payload_offset), int64_t(n), t_min, t_max,
                              int32_t(offset_ - payload_offset)});
  packet_.clear();
}

void Aedat4Writer::close()
{
  if (!f_)
    return;
  flushPacket();
  // FileDataTable: [size][root=16][FTAB][vtable 6,8,4][pad][table: soffset 8, vector offset]
  // [count][offsets...][entry vtable: 14 bytes][pad to 8][48-byte entry tables]
  const int64_t table_pos = int64_t(offset_);
  std::vector<uint8_t> b;
  put<uint32_t>(b, 4, 20 - 4);
  b.resize(12);
  std::memcpy(b.data() + 8, "FTAB", 4);
  put<uint16_t>(b, 12, 6);
  put<uint16_t>(b, 14, 8);
  put<uint16_t>(b, 16, 4);
  put<int32_t>(b, 20, 20 - 12);
  put<uint32_t>(b, 24, 28 - 24);
  const size_t n = table_.size();
  put<uint32_t>(b, 28, uint32_t(n));
  b.resize(32 + 4 * n, 0);
  padTo(b, 4);
  const size_t vt = b.size();
  put<uint16_t>(b, vt, 14);
  put<uint16_t>(b, vt + 2, 48);
  const uint16_t offs[5] = {8, 16, 24, 32, 40};
  for (int i = 0; i < 5; ++i)
    put<uint16_t>(b, vt + 4 + 2 * i, offs[i]);
  padTo(b, 8);
  for (size_t i = 0; i < n; ++i)
  {
    const size_t e = b.size();
    const TableEntry& t = table_[i];
    b.resize(e + 48, 0);
    put<int32_t>(b, e, int32_t(e - vt));
    put<int64_t>(b, e + 8, t.byte_offset);
    put<int32_t>(b, e + 16, 0);  // PacketInfo {StreamID, Size}
    put<int32_t>(b, e + 20, t.size);
    put<int64_t>(b, e + 24, t.elements);
    put<int64_t>(b, e + 32, t.t_start);
    put<int64_t>(b, e + 40, t.t_end);
    put<uint32_t>(b, 32 + 4 * i, uint32_t(e - (32 + 4 * i)));
  }
  put<uint32_t>(b, 0, uint32_t(b.size() - 4));
  writeCompressed(0, b, false);
  bool ok = std::fseek(f_, long(table_pos_field_), SEEK_SET) == 0 && std::fwrite(&table_pos, 1, 8, f_) == 8;
  ok = (std::fclose(f_) == 0) && ok;
  f_ = nullptr;
  if (!ok)
    throw EventFormatError(path_ + ": writing the data table failed");
}
}  // namespace formats
}  // namespace dvs_driver
