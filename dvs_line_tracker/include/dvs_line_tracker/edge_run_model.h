#pragma once
// Where an edge lies inside a pixel at the moment the pixel fires (sub-pixel edge positions).
//
// A DVS pixel fires each time its log intensity has moved by the contrast threshold C since its
// last event. While an edge between intensities I_dark and I_bright = rho * I_dark sweeps over
// a pixel, the pixel fires a run of about ln(rho) / C events of one polarity, the k-th when the
// covered fraction of the pixel has reached a value fixed by k, C and rho: ON events (the bright
// side entering) fire when the bright fraction b_k = (exp((k + 1/2) C) - 1) / (rho - 1), OFF
// events when the dark fraction d_k = (1 - exp(-(k + 1/2) C)) / (1 - 1 / rho) (the pixel's
// reference level sits half a step inside the saturated level on average). The edge then lies
// (dark fraction - 1/2) px from the pixel centre towards the bright side: from +0.43 px for the
// first ON event to -0.5 px for the last, instead of a constant offset.
//
// Each pixel's log level (above the dark side's, in [C/2, ln(rho) - C/2]) is integrated from its
// events. A run that follows a full sweep (the previous run ended within one step of its far
// bound) restarts from the saturated bound, so threshold mismatch does not accumulate; a run that
// follows a partial one (the edge turned back inside the pixel, as when a motion stops or
// reverses) continues from where that one ended. A pixel's first run starts from the saturated
// bound. With rho = 9, C = 0.3 this cuts the error of the event positions from 0.27 px (constant
// offset) to 0.11 px RMS (BENCHMARKS.md).
//
// C is learned from the events when not given: a full sweep yields floor(ln(rho) / C - u)
// events (u uniform in [0, 1)), so the mean length of the completed runs of >= 3 events is
// ln(rho) / C - 1/2. Runs complete only when a pixel's polarity changes, i.e. when the next edge
// crosses it, which in slow motion takes long (the flip: ~0.5 s for the first 1000): until then
// a prior C is used (events placed with the model from the start measured better than with the
// constant offset, even with the prior 17 % off either way or 50 % too high; BENCHMARKS.md).
//
// Per event: five bytes of state per pixel and one multiplication (the pixel's intensity is kept
// rather than its log level: no exp per event); nothing allocates.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace dvs_line_tracker
{
struct EdgeRunModelParams
{
  bool enabled = true;               ///< false: every event gets `constant_offset_px`
  double contrast_threshold = 0;     ///< C (log intensity); 0: learn it from the run lengths
  double prior_threshold = 0.3;      ///< C used while learning, until enough runs were seen (0: the constant offset instead)
  double edge_contrast_ratio = 9.0;  ///< rho = bright / dark intensity of the tracked edges
  double constant_offset_px = 0.15;  ///< offset used when disabled (and while learning without a prior)
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
    const size_t i = static_cast<size_t>(y) * width_ + x;
    uint8_t& run = runs_[i];
    const uint8_t polarity_bit = polarity ? 0x80 : 0;
    const bool new_run = run == 0 || (run & 0x80) != polarity_bit;
    if (new_run)
    {
      const int finished = run & 0x7f;
      if (finished >= 3)
        recordCompletedRun(finished);
      run = polarity_bit | 1;
    }
    else if ((run & 0x7f) < kMaxRun)
      ++run;
    if (!active_)
      return params_.constant_offset_px;
    // The pixel's intensity relative to dark, exp(level): one multiplication per event instead
    // of an exp. A new run restarts from the saturated bound after a full sweep (or in a fresh
    // pixel), and continues from the previous run's end after a partial one.
    float& intensity = intensities_[i];
    if (new_run && (intensity < 0 || (polarity ? intensity <= low_step_ : intensity >= high_step_)))
      intensity = static_cast<float>(polarity ? exp_low_ : exp_high_);
    // std::min / std::max, not fmin / fmax: the same for these finite values, and inlined (fmin
    // and fmax were two library calls per event).
    intensity = static_cast<float>(
        std::min(exp_high_, std::max(exp_low_, intensity * (polarity ? step_up_ : step_down_))));
    return offsetAtIntensity(intensity);
  }

  /// The offset of the k-th event (k >= 1) of a run that started from saturation, for threshold
  /// C and contrast ratio rho.
  static double runOffset(bool polarity, int k, double threshold, double contrast_ratio);

  /// The threshold in use (given, prior or learned); 0 while the constant offset is used.
  double threshold() const { return active_ ? threshold_ : 0.0; }
  /// Mean length of the completed runs of >= 3 events seen so far (0 if none).
  double meanRunLength() const { return completed_runs_ ? run_length_sum_ / completed_runs_ : 0.0; }
  uint64_t completedRuns() const { return completed_runs_; }
  /// True once the threshold in use was learned from the runs (or given).
  bool thresholdLearned() const { return learned_; }
  const EdgeRunModelParams& params() const { return params_; }

  /// Forget the pixels' runs and levels (the learned threshold, a property of the sensor, is kept).
  void resetRuns();

private:
  /// Edge offset (px, towards the bright side) when the pixel's intensity is `intensity` times
  /// the dark one (exp of its log level; at least exp(C/2), so nothing cancels in - 1).
  double offsetAtIntensity(double intensity) const { return 0.5 - (intensity - 1.0) * inverse_ratio_span_; }
  void recordCompletedRun(int length);
  void useThreshold(double threshold);

  EdgeRunModelParams params_;
  int width_;
  std::vector<uint8_t> runs_;   ///< per pixel: polarity (bit 7), length of its current run (bits 0-6)
  std::vector<float> intensities_;  ///< per pixel: exp(log level above dark) at its last event; < 0: no event yet
  bool active_ = false;
  bool learned_ = false;
  double threshold_ = 0;
  // In intensity (exp of the log level above dark): the bounds, the bounds one step inside, one
  // step up and down, and 1 / (rho - 1).
  double exp_low_ = 1, exp_high_ = 1, low_step_ = 1, high_step_ = 1, step_up_ = 1, step_down_ = 1;
  double inverse_ratio_span_ = 0;
  double run_length_sum_ = 0;
  uint64_t completed_runs_ = 0;
  uint64_t next_update_ = 0;  ///< completed-run count at which the learned threshold is refreshed
};
}  // namespace dvs_line_tracker
