#include <dvs_line_tracker/edge_run_model.h>

#include <algorithm>

namespace dvs_line_tracker
{
EdgeRunModel::EdgeRunModel(int width, int height, const EdgeRunModelParams& params)
  : params_(params)
  , width_(width)
  , runs_(static_cast<size_t>(width) * height, 0)
  , intensities_(runs_.size(), -1.0f)
{
  next_update_ = static_cast<uint64_t>(std::max(1, params.min_learning_runs));
  if (params.enabled && params.contrast_threshold > 0)
  {
    useThreshold(params.contrast_threshold);
    learned_ = true;
  }
  else if (params.enabled && params.prior_threshold > 0)
    useThreshold(params.prior_threshold);
}

double EdgeRunModel::runOffset(bool polarity, int k, double threshold, double contrast_ratio)
{
  const double steps = (k + 0.5) * threshold;
  const double dark = polarity ? 1.0 - std::min(1.0, std::expm1(steps) / (contrast_ratio - 1.0))
                               : std::min(1.0, -std::expm1(-steps) / (1.0 - 1.0 / contrast_ratio));
  return dark - 0.5;
}

void EdgeRunModel::useThreshold(double threshold)
{
  threshold_ = threshold;
  // The log level's bounds above dark: half a step inside the saturated levels.
  const double low = 0.5 * threshold;
  const double high = std::max(low, std::log(params_.edge_contrast_ratio) - 0.5 * threshold);
  exp_low_ = std::exp(low);
  exp_high_ = std::exp(high);
  low_step_ = std::exp(low + threshold);
  high_step_ = std::exp(high - threshold);
  step_up_ = std::exp(threshold_);
  step_down_ = std::exp(-threshold_);
  inverse_ratio_span_ = 1.0 / (params_.edge_contrast_ratio - 1.0);
  active_ = true;
}

void EdgeRunModel::recordCompletedRun(int length)
{
  run_length_sum_ += length;
  ++completed_runs_;
  if (!params_.enabled || params_.contrast_threshold > 0 || completed_runs_ < next_update_)
    return;
  // Refresh at 1x, 2x, 4x ... the minimum, then every 64x.
  const uint64_t first = static_cast<uint64_t>(std::max(1, params_.min_learning_runs));
  next_update_ = std::min(next_update_ * 2, next_update_ + 64 * first);
  const double full_sweep = meanRunLength() + 0.5;
  useThreshold(std::log(params_.edge_contrast_ratio) / full_sweep);
  learned_ = true;
}

void EdgeRunModel::resetRuns()
{
  std::fill(runs_.begin(), runs_.end(), 0);
  std::fill(intensities_.begin(), intensities_.end(), -1.0f);
}
}  // namespace dvs_line_tracker
