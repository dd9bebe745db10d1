#pragma once
// Tracking-quality monitoring: every `quality_check_interval` events while tracking, the
// estimate is checked (finite, the map in front of the camera, enough visible segments, small
// residuals, attribution not collapsed); the first failed check is the reason the track is lost.
// Too few visible segments may be held for partial_view_grace_s when two of them meet at a
// corner (partialViewHeld(): the tracker then reports no pose).
// Attribution has collapsed when fewer than `min_attributed_ratio` of the events were attributed,
// no more than 1.5x what chance gives (background events land in the attribution bands of the
// visible segments in proportion to the bands' share of the image, so on a large, noisy sensor
// in slow motion a good track attributes few events, yet more than chance), and the events not
// attributed are structure rather than noise (at least `min_unattributed_structure` of them next
// to two others: when the camera pauses, its edges stop firing and only noise is left, which
// says nothing against the pose; a wrong pose leaves the real edges' events unattributed). A
// track that slipped also shows as a drop of its attributed share far below its own level
// (`attribution_drop_ratio`) while the rest is structure and its residuals grew. A track on a
// pose that fits some sides and puts another where no edge is shows as a side that sweeps
// pixels without events while its edge fires nearby, unexplained (silent_side_check.h,
// `loss_silent_side_ratio`).
#include <dvs_line_tracker/estimator_state.h>
#include <dvs_line_tracker/neighbour_activity.h>
#include <dvs_line_tracker/silent_side_check.h>
#include <dvs_line_tracker/tracker_params.h>

#include <cstdint>
#include <memory>
#include <string>

namespace dvs_line_tracker
{
/// Mean |point-to-line| distance (px) over all buffered points of visible segments.
double meanResidualPx(const EstimatorState& state);
/// Two visible segments meet at kCornerMinAngleDeg or more (the corner a brief partial view
/// tracks on, partial_view_grace_s).
constexpr double kCornerMinAngleDeg = 30.0;
bool holdsACorner(const EstimatorState& state);

class LossMonitor
{
public:
  /// The sensor's size and the horizon of the neighbour test (neighbour_activity.h) that tells
  /// structure from noise among the events not attributed (loss_neighbour_events, scaled to the
  /// sensor). A size of 0 x 0: no chance level and no noise test (the
  /// attribution check is the fixed ratio only).
  /// `polygons`: the map's polygons as segment indices (silent_side_check.h; empty: one group
  /// of `num_segments`).
  LossMonitor(const LineTrackerParams& params, int width, int height, int horizon_events, int num_segments = 0,
              const std::vector<std::vector<int>>& polygons = {});

  /// Count one event at pixel (x, y) (ideal position `p`) processed while tracking;
  /// `segments` (optional, two entries, -1 for none): the segments it was attributed to;
  /// `projected` (optional): the projections of now, for where an unexplained event lies.
  void countEvent(bool attributed, int x, int y, const int* segments = nullptr, const Eigen::Vector2d* p = nullptr,
                  const std::vector<ProjectedSegment>* projected = nullptr)
  {
    ++events_;
    if (attributed)
    {
      ++attributed_;
      if (segments)
      {
        silent_sides_.countAttributed(segments[0]);
        silent_sides_.countAttributed(segments[1]);
      }
    }
    else if (!activity_ || activity_->add(x, y))
    {
      ++structured_;
      if (activity_ && p && projected)
        silent_sides_.countUnexplained(*p, *projected);
    }
  }
  /// A check is due (every quality_check_interval events).
  bool due() const { return events_ >= static_cast<uint64_t>(params_.quality_check_interval); }
  /// "" while the track is good, else why it is lost. Starts the next interval. Expects the
  /// state's visibility refreshed (EventUpdater::refresh). `t_ns`: the event time of the check
  /// (how long too few segments have been in view, partial_view_grace_s).
  std::string check(const EstimatorState& state, int64_t t_ns = 0);
  /// Fewer than min_visible_segments are in view, and the track is held (partial_view_grace_s).
  bool partialViewHeld() const { return too_few_since_ns_ != kNever; }
  /// A new interval.
  void reset() { events_ = attributed_ = structured_ = 0; }
  /// A new track: a new interval, and the track's attribution level forgotten.
  void restart()
  {
    reset();
    reference_ratio_ = -1;
    too_few_since_ns_ = kNever;
    silent_sides_.restart();
  }

private:
  const LineTrackerParams& params_;
  double image_area_px_;
  std::unique_ptr<NeighbourActivity> activity_;  ///< over the unattributed events only
  SilentSideCheck silent_sides_;
  uint64_t events_ = 0, attributed_ = 0, structured_ = 0;
  /// The track's attribution level: a running mean of the attributed shares of its checks that
  /// passed, quick to rise and slow to fall (a slip that drifts over many checks stays below it:
  /// -1 before the first check).
  double reference_ratio_ = -1;
  /// Since when fewer than min_visible_segments are in view (kNever: enough are).
  static constexpr int64_t kNever = INT64_MIN;
  int64_t too_few_since_ns_ = kNever;
  static constexpr double kReferenceRise = 0.1, kReferenceFall = 0.01;
  /// The attribution drop (attribution_drop_ratio) counts for tracks whose level is at least
  /// this (with less, a check's share varies too much: noisy large sensors), when at least this
  /// share of the unattributed events is structure and the buffers' mean residual is at least
  /// this (a good track in clutter keeps its events on its lines: 0.1-0.3 px).
  static constexpr double kDropMinReference = 0.5, kDropMinStructure = 0.5, kDropMinResidualPx = 0.4;
};
}  // namespace dvs_line_tracker
