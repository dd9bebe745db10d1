#include <dvs_line_tracker/loss_monitor.h>

#include <algorithm>
#include <cmath>

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

bool holdsACorner(const EstimatorState& state)
{
  // Two lines in view at kCornerMinAngleDeg or more to each other (parallel ones leave the
  // motion along them free).
  static const double min_sin = std::sin(kCornerMinAngleDeg * M_PI / 180.0);
  for (size_t i = 0; i < state.projected.size(); ++i)
    for (size_t j = i + 1; state.projected[i].visible && j < state.projected.size(); ++j)
      if (state.projected[j].visible &&
          std::abs(state.projected[i].dir.x() * state.projected[j].dir.y() -
                   state.projected[i].dir.y() * state.projected[j].dir.x()) >= min_sin)
        return true;
  return false;
}

LossMonitor::LossMonitor(const LineTrackerParams& params, int width, int height, int horizon_events,
                         int num_segments, const std::vector<std::vector<int>>& polygons)
  : params_(params)
  , image_area_px_(static_cast<double>(std::max(width, 0)) * std::max(height, 0))
  , silent_sides_(num_segments, polygons, params.loss_silent_side_ratio)
{
  if (width > 0 && height > 0)
    activity_ = std::make_unique<NeighbourActivity>(width, height, std::max(horizon_events, 1), 2);
}

std::string LossMonitor::check(const EstimatorState& state, int64_t t_ns)
{
  const double ratio = events_ > 0 ? static_cast<double>(attributed_) / events_ : 1.0;
  const uint64_t unattributed = events_ - attributed_;
  const double structured = unattributed > 0 ? static_cast<double>(structured_) / unattributed : 0.0;
  reset();
  if (!state.pose.allFinite())
    return "the pose is not finite";
  // (A segment partly behind the camera is clipped at the near plane and still tracked.)
  for (const auto& s : state.projected)
    if (!s.in_front)
      return "a map segment is wholly behind the camera";
  const int visible = state.visibleSegments();
  if (visible >= params_.min_visible_segments)
    too_few_since_ns_ = kNever;
  else
  {
    // Two lines still hold four of the six degrees of freedom, the damping the rest for a
    // moment: a brief partial view (partial_view_grace_s) does not cost the track.
    if (too_few_since_ns_ == kNever)
      too_few_since_ns_ = t_ns;
    if (t_ns - too_few_since_ns_ >= std::llround(params_.partial_view_grace_s * 1e9) || !holdsACorner(state))
      return "segments left the view (" + std::to_string(visible) + " visible)";
  }
  const double residual = meanResidualPx(state);
  if (residual > params_.max_mean_residual_px)
    return "residuals grew (mean " + std::to_string(residual) + " px)";
  const std::string silent = silent_sides_.check(state.projected, t_ns);
  if (!silent.empty())
    return silent;
  // Chance level: the share of the image within the attribution distance of a visible segment.
  double band_px = 0;
  for (const auto& seg : state.projected)
    if (seg.visible)
      band_px += seg.visible_length * 2.0 * params_.attribution.max_orthogonal_px;
  const double chance = image_area_px_ > 0 ? std::min(1.0, band_px / image_area_px_) : 1.0;
  // At chance level the attribution tells nothing when the events not attributed are noise too
  // (a camera pausing in front of a noisy sensor: its edges stop firing, the pose stays right);
  // the track is lost when they hold structure the map does not explain.
  if (ratio < params_.min_attributed_ratio && ratio < 1.5 * chance && structured >= params_.min_unattributed_structure)
    return "attribution collapsed (" + std::to_string(100.0 * ratio) + " % of events attributed, " +
           std::to_string(100.0 * structured) + " % of the rest next to each other)";
  // A track that slipped onto a wrong pose (frozen while part of the map was occluded and the
  // camera moved on) still finds events near its lines where they cross the real edges, so its
  // attributed share stays above min_attributed_ratio; but it falls far below the level this
  // track kept, what it no longer explains is edges, and its buffers sit off their lines.
  if (params_.attribution_drop_ratio > 0 && reference_ratio_ >= kDropMinReference &&
      ratio < params_.attribution_drop_ratio * reference_ratio_ && structured >= kDropMinStructure &&
      residual >= kDropMinResidualPx)
    return "attribution dropped (" + std::to_string(100.0 * ratio) + " % of events attributed, this track's level " +
           std::to_string(100.0 * reference_ratio_) + " %; " + std::to_string(100.0 * structured) +
           " % of the rest next to each other; mean residual " + std::to_string(residual) + " px)";
  reference_ratio_ = reference_ratio_ < 0 ? ratio
                                          : reference_ratio_ + (ratio > reference_ratio_ ? kReferenceRise : kReferenceFall) *
                                                                   (ratio - reference_ratio_);
  return "";
}
}  // namespace dvs_line_tracker
