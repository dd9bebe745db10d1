#pragma once
// Latency percentiles of a live run in fixed memory (ROS-free): a histogram of durations with
// logarithmic bins, 16 per factor of 2 (a quantile is known within 4.4 %), from 100 ns to
// about 27 min; the exact maximum is kept. add() does no allocation (a few arithmetic
// operations and one increment), so the tracker can count every event. Counts are weighted, so
// that one packet-level duration is counted for each of the packet's events at once.
#include <array>
#include <cstdint>
#include <string>

namespace dvs_line_tracker
{
class LatencyHistogram
{
public:
  /// Count `weight` samples of `seconds` (below 100 ns: the first bin; beyond the range: the last;
  /// a negative or NaN duration is counted in invalid() only).
  void add(double seconds, uint64_t weight = 1);
  void reset();
  uint64_t count() const { return count_; }
  uint64_t invalid() const { return invalid_; }
  /// The q-quantile (0 < q <= 1) in seconds: the upper edge of the bin that holds it, at most the
  /// maximum; 0 when empty.
  double quantile(double q) const;
  double max() const { return max_; }
  /// "p50 / p99 / max = 0.41 / 1.20 / 3.05 ms (N)" or "no samples".
  std::string summaryMs() const;

  static constexpr int kBinsPerOctave = 16;
  static constexpr int kOctaves = 34;  ///< 100 ns * 2^34 = 1718 s
  static constexpr double kMinSeconds = 1e-7;

private:
  std::array<uint64_t, kBinsPerOctave * kOctaves> bins_{};
  uint64_t count_ = 0;
  uint64_t invalid_ = 0;
  double max_ = 0;
};
}  // namespace dvs_line_tracker
