#pragma once
// Base of the readers whose decoders write into raw event memory: read() lets the decoder fill
// the reader's own buffer (kPiece events, cache-resident, allocated once) and appends that to the
// caller's vector, which is so written once and never zero-filled first (resize() would be).
// A decoder may write up to kSlack events past the requested end (one EVT 3.0 vector word, one
// AEDAT packet piece); those are kept for the next read(). Internal to the format readers.
#include <dvs_driver/formats/event_format.h>

#include <memory>

namespace dvs_driver
{
namespace formats
{
class BatchedReader : public EventFileReader
{
public:
  bool read(EventVector& out, size_t max_events) override;
  ReaderStats stats() const override { return stats_; }
  size_t takeTriggers(std::vector<TriggerEvent>& out) override;
  size_t takeImu(std::vector<ImuSample>& out) override;

protected:
  static constexpr size_t kSlack = 64;
  static constexpr size_t kMaxBatch = 1 << 16;
  static constexpr size_t kPiece = 4096;  ///< events decoded at a time into scratch_
  /// Decode into [p, end) (may write up to kSlack past end); return the new p. Returning a p
  /// below end means the file is exhausted.
  virtual Event* decode(Event* p, Event* end) = 0;
  /// Add a warning once per kind (kind = first word of the text).
  void warn(const std::string& text);

  ReaderStats stats_;
  std::vector<TriggerEvent> triggers_;
  std::vector<ImuSample> imu_;
  static constexpr size_t kMaxKept = 1 << 20;  ///< triggers / IMU samples kept between take calls
  bool finished_ = false;

private:
  std::unique_ptr<Event[]> scratch_;  ///< kPiece + kSlack events
  EventVector pending_;
  size_t pending_pos_ = 0;
};
}  // namespace formats
}  // namespace dvs_driver
