// AEDAT 4.0 streaming reader: layout in ../shared/reference/event-formats.md section 2.
#include <dvs_driver/formats/aedat4.h>
#include <dvs_driver/formats/batched_reader.h>
#include <dvs_driver/formats/chunked_file.h>
#include <dvs_driver/formats/compression.h>
#include <dvs_driver/formats/flatbuffer_view.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <climits>
#include <map>

namespace dvs_driver
{
namespace formats
{
const char* aedat4CompressionName(Aedat4Compression c)
{
  switch (c)
  {
    case Aedat4Compression::None:
      return "none";
    case Aedat4Compression::Lz4:
      return "LZ4";
    case Aedat4Compression::Lz4High:
      return "LZ4_HIGH";
    case Aedat4Compression::Zstd:
      return "ZSTD";
    case Aedat4Compression::ZstdHigh:
      return "ZSTD_HIGH";
  }
  return "?";
}

namespace
{
constexpr char kMagic[] = "#!AER-DAT4.0\r\n";
constexpr size_t kMagicSize = 14;

struct StreamInfo
{
  int id = -1;
  std::string type;  // typeIdentifier
  uint32_t width = 0, height = 0;
  std::string source;
};

std::string attrValue(const std::string& xml, size_t from, size_t to, const std::string& key)
{
  const std::string k = "<attr key=\"" + key + "\"";
  const size_t a = xml.find(k, from);
  if (a == std::string::npos || a >= to)
    return "";
  const size_t gt = xml.find('>', a);
  const size_t lt = xml.find("</attr>", gt);
  if (gt == std::string::npos || lt == std::string::npos || lt > to)
    return "";
  return xml.substr(gt + 1, lt - gt - 1);
}

/// Streams of the infoNode XML: the <node> children of "outInfo" holding a typeIdentifier.
std::vector<StreamInfo> parseInfoNode(const std::string& xml)
{
  std::vector<StreamInfo> streams;
  size_t out_info = xml.find("<node name=\"outInfo\"");
  if (out_info == std::string::npos)
    return streams;
  // Walk the nodes below outInfo, keeping the depth.
  size_t pos = xml.find('>', out_info);
  int depth = 0;
  while (pos != std::string::npos)
  {
    const size_t open = xml.find("<node ", pos), close = xml.find("</node>", pos);
    if (close == std::string::npos)
      break;
    if (open != std::string::npos && open < close)
    {
      if (depth == 0)
      {
        // A stream node: its own attributes run to its first child node or its end.
        const size_t name_at = open + 6;
        StreamInfo s;
        const size_t q1 = xml.find("name=\"", name_at);
        if (q1 != std::string::npos)
        {
          const size_t q2 = xml.find('"', q1 + 6);
          char* endp = nullptr;
          const std::string name = xml.substr(q1 + 6, q2 - q1 - 6);
          const long id = std::strtol(name.c_str(), &endp, 10);
          if (!name.empty() && *endp == 0)
            s.id = int(id);
        }
        // Scope: up to the matching </node> (find by depth counting).
        size_t scan = xml.find('>', open), d = 1, scope_end = std::string::npos;
        while (scan != std::string::npos)
        {
          const size_t o = xml.find("<node ", scan), c = xml.find("</node>", scan);
          if (c == std::string::npos)
            break;
          if (o != std::string::npos && o < c)
          {
            ++d;
            scan = o + 6;
          }
          else
          {
            if (--d == 0)
            {
              scope_end = c;
              break;
            }
            scan = c + 7;
          }
        }
        if (scope_end == std::string::npos)
          break;
        s.type = attrValue(xml, open, scope_end, "typeIdentifier");
        s.width = uint32_t(std::strtoul(attrValue(xml, open, scope_end, "sizeX").c_str(), nullptr, 10));
        s.height = uint32_t(std::strtoul(attrValue(xml, open, scope_end, "sizeY").c_str(), nullptr, 10));
        s.source = attrValue(xml, open, scope_end, "source");
        if (s.id >= 0 && !s.type.empty())
          streams.push_back(s);
        pos = scope_end + 7;
      }
      else
        pos = open + 6;
    }
    else
    {
      if (depth == 0)
        break;  // end of outInfo
      --depth;
      pos = close + 7;
    }
  }
  return streams;
}

class Aedat4Reader : public BatchedReader
{
public:
  explicit Aedat4Reader(const std::string& path) : file_(path, 1 << 16)
  {
    stats_.file_size = file_.size();
    uint8_t head[kMagicSize + 4];
    if (file_.read(head, sizeof head) != sizeof head || std::memcmp(head, "#!AER-DAT4.", 11) != 0)
      throw EventFormatError(path + ": not an AEDAT 4 file (no #!AER-DAT4.0 line)");
    if (std::memcmp(head, kMagic, kMagicSize) != 0)
      throw EventFormatError(path + ": AEDAT version '" + std::string(reinterpret_cast<char*>(head) + 2, 10) +
                             "' is not supported (4.0 is)");
    const uint32_t n = loadLE<uint32_t>(head + kMagicSize);
    if (n < 12 || n > (64u << 20) || n > file_.size())
      throw EventFormatError(path + ": AEDAT 4.0 IOHeader size " + std::to_string(n) + " is not plausible");
    std::vector<uint8_t> hdr(n);
    if (file_.read(hdr.data(), n) != n)
      throw EventFormatError(path + ": AEDAT 4.0 file ends inside its IOHeader");
    if (std::memcmp(hdr.data() + 4, "IOHE", 4) != 0)
      throw EventFormatError(path + ": AEDAT 4.0 IOHeader identifier is not IOHE");
    const FlatTable io = FlatTable::root(hdr.data(), n);
    if (!io.valid())
      throw EventFormatError(path + ": AEDAT 4.0 IOHeader flatbuffer is malformed");
    const int32_t comp = io.scalar<int32_t>(0, 0);
    if (comp < 0 || comp > 4)
      throw EventFormatError(path + ": AEDAT 4.0 compression " + std::to_string(comp) +
                             " is not supported (none, LZ4, LZ4_HIGH, ZSTD, ZSTD_HIGH are)");
    compression_ = Aedat4Compression(comp);
    const int64_t table_pos = io.scalar<int64_t>(1, -1);
    std::string xml;
    io.string(2, xml);
    data_start_ = kMagicSize + 4 + n;

    streams_ = parseInfoNode(xml);
    for (const auto& s : streams_)
      if (s.type == "EVTS" && (evts_ < 0 || s.id < evts_))
      {
        evts_ = s.id;
        width_ = s.width;
        height_ = s.height;
      }
    for (const auto& s : streams_)
      if (s.type == "IMUS" && (imus_ < 0 || s.id < imus_))
        imus_ = s.id;
    if (evts_ < 0)
      throw EventFormatError(path + ": AEDAT 4.0 file has no event stream (no typeIdentifier EVTS in its info)");
    limit_x_ = width_ ? width_ : 32768;
    limit_y_ = height_ ? height_ : 32768;
    if (!width_ || !height_)
      warn("size: the AEDAT 4.0 event stream info gives no sizeX/sizeY");

    if (table_pos >= 0)
      readTable(table_pos);
    else
      warn("no-table: the AEDAT 4.0 file has no data table (interrupted recording?); packets are scanned");
    end_of_packets_ = table_mode_ ? uint64_t(table_pos) : file_.size();
    scan_pos_ = data_start_;
  }

  uint32_t width() const override { return width_; }
  uint32_t height() const override { return height_; }
  std::string formatName() const override
  {
    return std::string("AEDAT 4.0 (") + aedat4CompressionName(compression_) + ")";
  }
  int64_t expectedEvents() const override { return expected_; }

protected:
  Event* decode(Event* p, Event* end) override
  {
    for (;;)
    {
      const size_t n = std::min<size_t>(cur_n_ - cur_, size_t(end - p));
      const uint8_t* q = elems_ + 16 * cur_;
      const uint32_t lx = limit_x_, ly = limit_y_;
      uint64_t oor = 0, bad_time = 0;
      // Microseconds whose nanoseconds would overflow int64 (~292 years): a corrupt packet
      // (found by fuzzing); skipped and counted, never multiplied.
      constexpr int64_t kMaxUs = INT64_MAX / 1000;
      for (size_t k = 0; k < n; ++k, q += 16)
      {
        const int64_t t = loadLE<int64_t>(q);
        const uint16_t x = loadLE<uint16_t>(q + 8), y = loadLE<uint16_t>(q + 10);  // negative -> huge
        if (t > kMaxUs || t < -kMaxUs)
          ++bad_time;
        else if (x < lx && y < ly)
          *p++ = Event{t * 1000, x, y, q[12] != 0};
        else
          ++oor;
      }
      cur_ += n;
      stats_.out_of_range += oor;
      stats_.invalid_events += bad_time;
      if (p >= end)
        return p;
      if (!nextPacket())
        return p;
    }
  }

private:
  void readTable(int64_t pos)
  {
    if (uint64_t(pos) < data_start_ || uint64_t(pos) >= file_.size())
    {
      warn("table: the AEDAT 4.0 data table position " + std::to_string(pos) +
           " lies outside the file (truncated file?); packets are scanned");
      return;
    }
    const size_t n = file_.size() - uint64_t(pos);
    std::vector<uint8_t> comp(n);
    file_.seek(uint64_t(pos));
    if (file_.read(comp.data(), n) != n)
      return;
    const uint8_t* buf = nullptr;
    size_t size = 0;
    if (!decompress(comp.data(), n, buf, size) || size < 12 || std::memcmp(buf + 8, "FTAB", 4) != 0)
    {
      warn("table: the AEDAT 4.0 data table cannot be decoded; packets are scanned");
      return;
    }
    const FlatTable t = FlatTable::root(buf + 4, size - 4);
    uint32_t count = 0;
    uint64_t first = 0;
    if (!t.valid() || !t.vector(0, 4, count, first))
    {
      warn("table: the AEDAT 4.0 data table is malformed; packets are scanned");
      return;
    }
    std::vector<Entry> entries;
    int64_t expected = 0;
    uint64_t others = 0, unknown = 0;
    for (uint32_t i = 0; i < count; ++i)
    {
      const uint64_t e = first + 4 * i;
      const FlatTable d = FlatTable::at(t.buffer(), t.bufferSize(), e + loadLE<uint32_t>(t.buffer() + e));
      const int64_t off = d.scalar<int64_t>(0, -1);
      const uint64_t info = d.fieldPos(1, 8);
      if (!d.valid() || !info)
      {
        warn("table: an AEDAT 4.0 data table entry is malformed; packets are scanned");
        return;
      }
      const int32_t stream = loadLE<int32_t>(t.buffer() + info), psize = loadLE<int32_t>(t.buffer() + info + 4);
      if (stream != evts_)
      {
        bool known = false;
        for (const auto& s : streams_)
          known |= s.id == stream;
        ++(known ? others : unknown);
        if (stream != imus_)
          continue;
      }
      if (off < int64_t(data_start_ + 8) || psize < 0 || off + psize > pos)
      {
        warn("table: an AEDAT 4.0 data table entry points outside the packets; packets are scanned");
        return;
      }
      entries.push_back(Entry{uint64_t(off), psize, stream == imus_});
      if (stream == evts_)
        expected += d.scalar<int64_t>(2, 0);
    }
    entries_ = std::move(entries);
    expected_ = expected;
    stats_.other_words += others;
    stats_.unknown_words += unknown;
    table_mode_ = true;
  }

  bool decompress(const uint8_t* src, size_t n, const uint8_t*& out, size_t& out_size)
  {
    std::string err;
    switch (compression_)
    {
      case Aedat4Compression::None:
        out = src;
        out_size = n;
        return true;
      case Aedat4Compression::Lz4:
      case Aedat4Compression::Lz4High:
        err = dec_.lz4(src, n, raw_);
        break;
      case Aedat4Compression::Zstd:
      case Aedat4Compression::ZstdHigh:
        err = dec_.zstd(src, n, raw_);
        break;
    }
    if (!err.empty())
    {
      last_error_ = err;
      return false;
    }
    out = raw_.data.get();
    out_size = raw_.size;
    return true;
  }

  void truncatedAt(uint64_t offset)
  {
    stats_.truncated = true;
    stats_.truncated_offset = offset;
    stats_.truncated_bytes = file_.size() - offset;
    warn("truncated: the AEDAT 4.0 file ends inside the packet at byte " + std::to_string(offset) + " (" +
         std::to_string(stats_.truncated_bytes) + " bytes ignored)");
  }

  /// Read, decompress and check the EVTS packet whose payload (size bytes) starts at `offset`.
  /// False when it is damaged (counted, warned) or truncated (then done_ is set).
  /// Read and decompress the payload (size bytes) at `offset`; false when damaged (counted,
  /// warned) or truncated (then done_ is set).
  bool readPayload(uint64_t offset, int32_t size, const uint8_t*& buf, size_t& n, const char* what)
  {
    if (offset + uint64_t(size) > file_.size())
    {
      truncatedAt(offset - 8);
      done_ = true;
      return false;
    }
    comp_.size = 0;
    comp_.reserve(size_t(size));
    file_.seek(offset);
    if (file_.read(comp_.data.get(), size_t(size)) != size_t(size))
    {
      truncatedAt(offset - 8);
      done_ = true;
      return false;
    }
    stats_.bytes_read = offset + size;
    if (!decompress(comp_.data.get(), size_t(size), buf, n))
    {
      ++stats_.damaged_packets;
      warn(std::string("damaged: an AEDAT 4.0 ") + what + " packet at byte " + std::to_string(offset - 8) +
           " cannot be decompressed (" + last_error_ + "); skipped");
      return false;
    }
    return true;
  }

  /// Decode an IMUS packet into imu_ (Imu tables: t, temperature, accelerometer xyz [g],
  /// gyroscope xyz [deg/s], magnetometer xyz).
  void loadImuPacket(uint64_t offset, int32_t size)
  {
    const uint8_t* buf = nullptr;
    size_t n = 0;
    if (!readPayload(offset, size, buf, n, "IMU"))
      return;
    uint32_t count = 0;
    uint64_t first = 0;
    FlatTable t;
    if (n >= 12 && std::memcmp(buf + 8, "IMUS", 4) == 0)
      t = FlatTable::root(buf + 4, n - 4);
    if (!t.valid() || !t.vector(0, 4, count, first))
    {
      ++stats_.damaged_packets;
      warn("damaged: an AEDAT 4.0 IMU packet at byte " + std::to_string(offset - 8) +
           " is not an IMUS flatbuffer; skipped");
      return;
    }
    constexpr double kDeg = M_PI / 180.0;  // the file: accelerometer in g, gyroscope in deg/s
    for (uint32_t k = 0; k < count; ++k)
    {
      const uint64_t e = first + 4 * k;
      const FlatTable imu = FlatTable::at(t.buffer(), t.bufferSize(), e + loadLE<uint32_t>(t.buffer() + e));
      if (!imu.valid())
      {
        ++stats_.damaged_packets;
        return;
      }
      ImuSample s;
      const int64_t t_us = imu.scalar<int64_t>(0, 0);
      if (t_us > INT64_MAX / 1000 || t_us < -(INT64_MAX / 1000))
      {
        ++stats_.damaged_packets;  // a time no clock gives: corrupt
        return;
      }
      s.t_ns = t_us * 1000;
      s.temperature_c = imu.scalar<float>(1, 0.0f);
      for (unsigned a = 0; a < 3; ++a)
      {
        s.accel[a] = double(imu.scalar<float>(2 + a, 0.0f)) * kStandardGravity;
        s.gyro[a] = double(imu.scalar<float>(5 + a, 0.0f)) * kDeg;
      }
      ++stats_.imu_samples;
      if (imu_.size() < kMaxKept)
        imu_.push_back(s);
    }
  }

  bool loadPacket(uint64_t offset, int32_t size)
  {
    const uint8_t* buf = nullptr;
    size_t n = 0;
    if (!readPayload(offset, size, buf, n, "event"))
      return false;
    return parseEventPacket(offset, buf, n);
  }

  bool parseEventPacket(uint64_t offset, const uint8_t* buf, size_t n)
  {
    uint32_t count = 0;
    uint64_t first = 0;
    FlatTable t;
    if (n >= 12 && std::memcmp(buf + 8, "EVTS", 4) == 0)
      t = FlatTable::root(buf + 4, n - 4);
    if (!t.valid() || !t.vector(0, 16, count, first))
    {
      ++stats_.damaged_packets;
      warn("damaged: an AEDAT 4.0 event packet at byte " + std::to_string(offset - 8) +
           " is not an EVTS EventPacket flatbuffer; skipped");
      return false;
    }
    elems_ = buf + 4 + first;
    cur_ = 0;
    cur_n_ = count;
    return true;
  }

  bool nextPacket()
  {
    while (!done_)
    {
      if (table_mode_)
      {
        if (next_entry_ >= entries_.size())
        {
          done_ = true;
          stats_.bytes_read = file_.size();
          break;
        }
        const Entry& e = entries_[next_entry_++];
        if (e.imu)
        {
          loadImuPacket(e.offset, e.size);
          continue;
        }
        if (loadPacket(e.offset, e.size))
          return true;
        continue;
      }
      // Scan: [int32 stream id][int32 size][payload]
      if (scan_pos_ >= end_of_packets_)
      {
        done_ = true;
        break;
      }
      uint8_t h[8];
      file_.seek(scan_pos_);
      const size_t got = file_.read(h, 8);
      if (got < 8)
      {
        truncatedAt(scan_pos_);
        done_ = true;
        break;
      }
      const int32_t stream = loadLE<int32_t>(h), size = loadLE<int32_t>(h + 4);
      const uint64_t payload = scan_pos_ + 8;
      if (size < 0 || payload + uint64_t(size) > end_of_packets_)
      {
        truncatedAt(scan_pos_);
        done_ = true;
        break;
      }
      scan_pos_ = payload + uint64_t(size);
      stats_.bytes_read = scan_pos_;
      if (stream == evts_)
      {
        if (loadPacket(payload, size))
          return true;
        continue;
      }
      bool known = false;
      for (const auto& s : streams_)
        known |= s.id == stream;
      if (stream == imus_)
        loadImuPacket(payload, size);
      if (known)
        ++stats_.other_words;
      else
      {
        ++stats_.unknown_words;
        warn("unknown-stream: AEDAT 4.0 packets of a stream id not in the file's info are skipped");
      }
    }
    return false;
  }

  struct Entry
  {
    uint64_t offset;
    int32_t size;
    bool imu;  // an IMUS packet (else EVTS)
  };

  ChunkedFile file_;
  Aedat4Compression compression_ = Aedat4Compression::None;
  std::vector<StreamInfo> streams_;
  int evts_ = -1, imus_ = -1;
  uint32_t width_ = 0, height_ = 0, limit_x_ = 0, limit_y_ = 0;
  uint64_t data_start_ = 0, end_of_packets_ = 0, scan_pos_ = 0;
  bool table_mode_ = false, done_ = false;
  std::vector<Entry> entries_;
  size_t next_entry_ = 0;
  int64_t expected_ = -1;
  Decompressor dec_;
  ByteBuffer comp_, raw_;
  std::string last_error_;
  const uint8_t* elems_ = nullptr;
  size_t cur_ = 0, cur_n_ = 0;
};
}  // namespace

std::unique_ptr<EventFileReader> openAedat4(const std::string& path)
{
  return std::make_unique<Aedat4Reader>(path);
}
}  // namespace formats
}  // namespace dvs_driver
