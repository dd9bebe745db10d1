#pragma once
// Decoder of event_camera_msgs/EventPacket payloads (ros-event-camera), ROS-free: feed it each
// message's (encoding, width, height, time_base, events bytes) in order; decoder state carries
// across messages (an EVT 3.0 stream is cut at arbitrary words between messages).
// Encodings (../shared/reference/event-formats.md section 4):
//  - "evt3": Prophesee EVT 3.0 words (Evt3Decoder); time_base unused; t = sensor time (us x 1000);
//  - "mono": 64-bit little-endian words: bits 0-31 dt, 32-47 x, 48-62 y, 63 polarity;
//    t_ns = time_base + dt;
//  - "libcaer": 8-byte libcaer polarity events {uint32 data, int32 timestamp us}: bit 0 valid
//    (invalid events skipped and counted), bit 1 polarity, bits 2-16 y, 17-31 x;
//    t_ns = time_base + ts x 1000, plus 2^31 us per drop of ts inside a message (as
//    event_camera_codecs does).
// Any other encoding (libcaer_cmp, trigger, ...) throws EventFormatError naming it.
#include <dvs_driver/formats/evt3_decoder.h>

#include <memory>
#include <string>

namespace dvs_driver
{
namespace formats
{
class EventPacketDecoder
{
public:
  /// True for the encodings decode() accepts.
  static bool supports(const std::string& encoding);

  /// Decode one message's payload, appending its events to `out` (and EVT 3.0 external
  /// triggers to `triggers` if not null). The first message fixes encoding and sensor size; a
  /// later message with another encoding or size throws EventFormatError (call reset() for a new
  /// stream). Events outside width x height (when not 0) are dropped and counted. A payload
  /// whose length is not a whole number of words: the incomplete word is dropped, counted in
  /// stats().truncated_bytes, warned. Allocates only when `out` must grow.
  void decode(const std::string& encoding, uint32_t width, uint32_t height, uint64_t time_base,
              const uint8_t* data, size_t size, EventVector& out, std::vector<TriggerEvent>* triggers = nullptr);

  /// Forget the stream (next message starts a new one).
  void reset();

  /// events, triggers, unknown_words, out_of_range, before_time, invalid_events,
  /// time_wraps, time_backsteps, bytes_read (payload bytes), warnings.
  const ReaderStats& stats() const { return stats_; }
  const std::string& encoding() const { return encoding_; }
  uint64_t messages() const { return messages_; }

private:
  enum class Kind
  {
    None,
    Evt3,
    Mono,
    Libcaer
  };
  void warn(const std::string& text);
  void decodeEvt3(const uint8_t* data, size_t words, EventVector& out, std::vector<TriggerEvent>* triggers);
  void decodeMono(uint64_t time_base, const uint8_t* data, size_t n, EventVector& out);
  void decodeLibcaer(uint64_t time_base, const uint8_t* data, size_t n, EventVector& out);

  Kind kind_ = Kind::None;
  std::string encoding_;
  uint32_t width_ = 0, height_ = 0;
  std::unique_ptr<Evt3Decoder> evt3_;
  uint64_t messages_ = 0;
  ReaderStats stats_;
};
}  // namespace formats
}  // namespace dvs_driver
