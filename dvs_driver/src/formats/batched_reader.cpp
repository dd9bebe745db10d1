#include <dvs_driver/formats/batched_reader.h>

#include <algorithm>

namespace dvs_driver
{
namespace formats
{
bool BatchedReader::read(EventVector& out, size_t max_events)
{
  if (max_events == 0)
    return !(finished_ && pending_pos_ == pending_.size());
  const size_t n = std::min(max_events, kMaxBatch);
  size_t appended = 0;
  while (appended < n)
  {
    if (pending_pos_ < pending_.size())
    {
      const size_t k = std::min(n - appended, pending_.size() - pending_pos_);
      out.insert(out.end(), pending_.begin() + pending_pos_, pending_.begin() + pending_pos_ + k);
      pending_pos_ += k;
      appended += k;
      if (pending_pos_ == pending_.size())
      {
        pending_.clear();
        pending_pos_ = 0;
      }
      continue;
    }
    if (finished_)
      break;
    // Decode a piece into the reader's own buffer (cache-resident, allocated and constructed
    // once) and append it: the caller's vector is written once, never zero-filled first.
    if (!scratch_)
      scratch_.reset(new Event[kPiece + kSlack]);
    Event* const start = scratch_.get();
    Event* const end = start + std::min(n - appended, kPiece);
    Event* p = decode(start, end);
    if (p < end)
      finished_ = true;
    if (p > end)
    {
      pending_.assign(end, p);
      pending_pos_ = 0;
      p = end;
    }
    out.insert(out.end(), start, p);
    appended += static_cast<size_t>(p - start);
  }
  stats_.events += appended;
  return appended > 0;
}

size_t BatchedReader::takeTriggers(std::vector<TriggerEvent>& out)
{
  const size_t n = triggers_.size();
  out.insert(out.end(), triggers_.begin(), triggers_.end());
  triggers_.clear();
  return n;
}

size_t BatchedReader::takeImu(std::vector<ImuSample>& out)
{
  const size_t n = imu_.size();
  out.insert(out.end(), imu_.begin(), imu_.end());
  imu_.clear();
  return n;
}

void BatchedReader::warn(const std::string& text)
{
  const std::string kind = text.substr(0, text.find(' '));
  for (const auto& w : stats_.warnings)
    if (w.compare(0, kind.size() + 1, kind + " ") == 0 || w == kind)
      return;
  stats_.warnings.push_back(text);
}
}  // namespace formats
}  // namespace dvs_driver
