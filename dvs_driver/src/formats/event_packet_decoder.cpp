// event_camera_msgs/EventPacket payload decoding; see formats/event_packet_decoder.h.
#include <dvs_driver/formats/event_packet_decoder.h>

#include <algorithm>
#include <cstring>

namespace dvs_driver
{
namespace formats
{
namespace
{
inline uint64_t le64(const uint8_t* p)
{
  uint64_t v;
  std::memcpy(&v, p, 8);
#if __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  v = __builtin_bswap64(v);
#endif
  return v;
}

inline uint32_t le32(const uint8_t* p)
{
  uint32_t v;
  std::memcpy(&v, p, 4);
#if __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
  v = __builtin_bswap32(v);
#endif
  return v;
}
}  // namespace

bool EventPacketDecoder::supports(const std::string& encoding)
{
  return encoding == "evt3" || encoding == "mono" || encoding == "libcaer";
}

void EventPacketDecoder::reset()
{
  kind_ = Kind::None;
  encoding_.clear();
  width_ = height_ = 0;
  evt3_.reset();
  messages_ = 0;
  stats_ = ReaderStats();
}

void EventPacketDecoder::warn(const std::string& text)
{
  const std::string kind = text.substr(0, text.find(':'));
  for (const auto& w : stats_.warnings)
    if (w.compare(0, kind.size(), kind) == 0)
      return;
  stats_.warnings.push_back(text);
}

void EventPacketDecoder::decode(const std::string& encoding, uint32_t width, uint32_t height, uint64_t time_base,
                                const uint8_t* data, size_t size, EventVector& out,
                                std::vector<TriggerEvent>* triggers)
{
  if (kind_ == Kind::None)
  {
    if (encoding == "evt3")
      kind_ = Kind::Evt3;
    else if (encoding == "mono")
      kind_ = Kind::Mono;
    else if (encoding == "libcaer")
      kind_ = Kind::Libcaer;
    else
      throw EventFormatError("EventPacket encoding '" + encoding +
                             "' is not supported (evt3, mono and libcaer are)");
    encoding_ = encoding;
    width_ = width;
    height_ = height;
    if (kind_ == Kind::Evt3)
      evt3_ = std::make_unique<Evt3Decoder>(width, height, 0);
  }
  else if (encoding != encoding_ || width != width_ || height != height_)
    throw EventFormatError("EventPacket message " + std::to_string(messages_) + " has encoding '" + encoding +
                           "' and size " + std::to_string(width) + "x" + std::to_string(height) +
                           " but the stream started with '" + encoding_ + "' " + std::to_string(width_) + "x" +
                           std::to_string(height_));
  const size_t word = kind_ == Kind::Evt3 ? 2 : 8;
  const size_t whole = size / word;
  if (size % word != 0)
  {
    stats_.truncated = true;
    stats_.truncated_offset = stats_.bytes_read + whole * word;
    stats_.truncated_bytes += size % word;
    warn("truncated: EventPacket message " + std::to_string(messages_) + " has " + std::to_string(size) +
         " bytes, not a whole number of " + std::to_string(word) + "-byte words; the last " +
         std::to_string(size % word) + " bytes were dropped");
  }
  const size_t before = out.size();
  switch (kind_)
  {
    case Kind::Evt3:
      decodeEvt3(data, whole, out, triggers);
      break;
    case Kind::Mono:
      decodeMono(time_base, data, whole, out);
      break;
    default:
      decodeLibcaer(time_base, data, whole, out);
      break;
  }
  stats_.events += out.size() - before;
  stats_.bytes_read += size;
  ++messages_;
}

void EventPacketDecoder::decodeEvt3(const uint8_t* data, size_t words, EventVector& out,
                                    std::vector<TriggerEvent>* triggers)
{
  constexpr size_t kPiece = 4096;
  while (words > 0)
  {
    const size_t base = out.size();
    const size_t room = std::min(kPiece, words * Evt3Decoder::kMaxEventsPerWord);
    out.resize(base + room + Evt3Decoder::kMaxEventsPerWord);
    size_t used = 0;
    Event* p = evt3_->decode(data, words, out.data() + base, out.data() + base + room, used, stats_, triggers);
    out.resize(size_t(p - out.data()));
    data += used * 2;
    words -= used;
  }
}

void EventPacketDecoder::decodeMono(uint64_t time_base, const uint8_t* data, size_t n, EventVector& out)
{
  for (size_t i = 0; i < n; ++i, data += 8)
  {
    const uint64_t w = le64(data);
    const uint32_t x = uint32_t(w >> 32) & 0xFFFF, y = uint32_t(w >> 48) & 0x7FFF;
    if ((width_ && x >= width_) || (height_ && y >= height_))
    {
      ++stats_.out_of_range;
      continue;
    }
    Event e;
    e.t_ns = int64_t(time_base + (w & 0xFFFFFFFFull));
    e.x = uint16_t(x);
    e.y = uint16_t(y);
    e.polarity = (w >> 63) != 0;
    out.push_back(e);
  }
}

void EventPacketDecoder::decodeLibcaer(uint64_t time_base, const uint8_t* data, size_t n, EventVector& out)
{
  uint64_t high = time_base;
  int64_t last = 0;  // rollovers only inside a message (event_camera_codecs' rule)
  for (size_t i = 0; i < n; ++i, data += 8)
  {
    const uint32_t d = le32(data);
    const int64_t ts = int32_t(le32(data + 4));
    if (ts < last)
    {
      high += (uint64_t(1) << 31) * 1000;
      ++stats_.time_wraps;
    }
    last = ts;
    if ((d & 1) == 0)
    {
      ++stats_.invalid_events;
      continue;
    }
    const uint32_t x = (d >> 17) & 0x7FFF, y = (d >> 2) & 0x7FFF;
    if ((width_ && x >= width_) || (height_ && y >= height_))
    {
      ++stats_.out_of_range;
      continue;
    }
    Event e;
    e.t_ns = int64_t(high + uint64_t(ts) * 1000);
    e.x = uint16_t(x);
    e.y = uint16_t(y);
    e.polarity = ((d >> 1) & 1) != 0;
    out.push_back(e);
  }
}
}  // namespace formats
}  // namespace dvs_driver
