#pragma once
// Where an edge lies inside a pixel at the moment the pixel fires (sub-pixel edge positions).
//
// A DVS pixel fires each time its log intensity has moved by the contrast threshold C since its
// last event. While an edge between intensities I_dark and I_bright = rho * I_dark sweeps over
// a pixel, the pixel fires a run of about ln(rho) / C events of one polarity, the k-th when the
// covered fraction of the pixel has reached a value fixed by k, C and rho: ON events (the bright
// side entering) fire when the bright fraction b_k = (exp((k + 1/2) C) - 1) / (rho - 1), OFF
// events when the dark fraction d_k = (1 - exp(-(k + 1/2) C)) / (1 - 1 / rho) (the pixel's
// reference level sits half a step past the previous run's last level on average). The edge
// then lies (dark fraction - 1/2) px from the pixel centre towards the bright side: from +0.43 px
// for the first ON event to -0.5 px for the last, instead of a constant offset. With rho = 9,
// C = 0.3 this cuts the error of the event positions from 0.27 px to 0.12 px RMS (BENCHMARKS.md).
//
// C is learned from the events when not given: a full sweep yields floor(ln(rho) / C - u)
// events (u uniform in [0, 1)), so the mean length of the completed runs of >= 3 events is
// ln(rho) / C - 1/2. Until enough runs were seen, a constant offset is used.
//
// Per event: one byte of state per pixel and a table lookup; nothing allocates.
#include <cmath>
#include <cstdint>
#include <vector>

namespace dvs_line_tracker
{
struct EdgeRunModelParams
{
  bool enabled = true;               ///< false: every event gets `constant_offset_px`
  double contrast_threshold = 0;     ///< C (log intensity); 0: learn it from the run lengths
  double edge_contrast_ratio = 9.0;  ///< rho = bright / dark intensity of the tracked edges
  double constant_offset_px = 0.15;  ///< offset used when disabled and until C is learned
  int min_learning_runs = 1000;      ///< completed runs before the learned C is used
};

class EdgeRunModel
{
public:
  static constexpr int kMaxRun = 127;

  EdgeRunModel(int width, int height, const EdgeRunModelParams& params);

  /// Record an event of pixel (x, y) (inside the sensor) and return the offset (px) of the edge
  /// from the pixel centre towards the edge's bright side at the time of the event.
  double update(int x, int y, bool polarity)
  {
    uint8_t& run = runs_[static_cast<size_t>(y) * width_ + x];
    const uint8_t polarity_bit = polarity ? 0x80 : 0;
    if ((run & 0x80) != polarity_bit || run == 0)
    {
      const int finished = run & 0x7f;
      if (finished >= 3 && (run & 0x80) != polarity_bit)
        recordCompletedRun(finished);
      run = polarity_bit | 1;
    }
    else if ((run & 0x7f) < kMaxRun)
      ++run;
    return active_ ? offsets_[polarity ? 1 : 0][(run & 0x7f) - 1] : params_.constant_offset_px;
  }

  /// The offset of the k-th event (k >= 1) of a run for threshold C and contrast ratio rho.
  static double runOffset(bool polarity, int k, double threshold, double contrast_ratio);

  /// The threshold in use (given or learned); 0 while the constant offset is used.
  double threshold() const { return active_ ? threshold_ : 0.0; }
  /// Mean length of the completed runs of >= 3 events seen so far (0 if none).
  double meanRunLength() const { return completed_runs_ ? run_length_sum_ / completed_runs_ : 0.0; }
  uint64_t completedRuns() const { return completed_runs_; }
  const EdgeRunModelParams& params() const { return params_; }

  /// Forget the pixels' runs (the learned threshold, a property of the sensor, is kept).
  void resetRuns();

private:
  void recordCompletedRun(int length);
  void buildTable(double threshold);

  EdgeRunModelParams params_;
  int width_;
  std::vector<uint8_t> runs_;  ///< per pixel: polarity (bit 7), length of its current run (bits 0-6)
  double offsets_[2][kMaxRun];  ///< [polarity][run length - 1]
  bool active_ = false;
  double threshold_ = 0;
  double run_length_sum_ = 0;
  uint64_t completed_runs_ = 0;
  uint64_t next_update_ = 0;  ///< completed-run count at which the learned threshold is refreshed
};
}  // namespace dvs_line_tracker
