#include <dvs_line_tracker/loss_monitor.h>

#include <algorithm>

namespace dvs_line_tracker
{
double meanResidualPx(const EstimatorState& state)
{
  double sum = 0;
  int count = 0;
  for (size_t i = 0; i < state.projected.size(); ++i)
  {
    if (!state.projected[i].visible)
      continue;
    for (int j = 0; j < state.buffers[i].size(); ++j)
    {
      sum += state.projected[i].orthogonalDistance(state.buffers[i].point(j));
      ++count;
    }
  }
  return count > 0 ? sum / count : 0.0;
}

std::string LossMonitor::check(const EstimatorState& state)
{
  const double ratio = events_ > 0 ? static_cast<double>(attributed_) / events_ : 1.0;
  reset();
  if (!state.pose.allFinite())
    return "the pose is not finite";
  for (const auto& s : state.projected)
    if (!s.in_front)
      return "part of the map is behind the camera";
  const int visible = state.visibleSegments();
  if (visible < params_.min_visible_segments)
    return "segments left the view (" + std::to_string(visible) + " visible)";
  const double residual = meanResidualPx(state);
  if (residual > params_.max_mean_residual_px)
    return "residuals grew (mean " + std::to_string(residual) + " px)";
  // Chance level: the share of the image within the attribution distance of a visible segment.
  double band_px = 0;
  for (const auto& seg : state.projected)
    if (seg.visible)
      band_px += seg.visible_length * 2.0 * params_.attribution.max_orthogonal_px;
  const double chance = image_area_px_ > 0 ? std::min(1.0, band_px / image_area_px_) : 1.0;
  if (ratio < params_.min_attributed_ratio && ratio < 1.5 * chance)
    return "attribution collapsed (" + std::to_string(100.0 * ratio) + " % of events attributed)";
  return "";
}
}  // namespace dvs_line_tracker
