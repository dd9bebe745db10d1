#pragma once
// A wrong pose that still fits some sides: the tracker's lines move with the camera, and a real
// edge moving across the sensor fires events in proportion to the area it sweeps (its contrast
// over the threshold per pixel crossed). After a bump the estimate can settle on a pose that
// matches two or three sides of a square seen at a steep angle and puts the last one where no
// edge is, while the real edge fires nearby, unexplained (re-acquisition sweep scenes 14 and 53:
// 9-21 % of the distance off for the rest of the run, never lost). So a side is silent when
// - it moved across the image (net, between its projection kSpanChecks snapshots ago and now,
//   so that the estimate's jitter does not add up to a motion), and
// - it attracted fewer than `ratio` of the events its polygon's densest side fired per px^2
//   swept (the reference's area summed snapshot by snapshot, which jitter only enlarges: the
//   comparison is conservative both ways, and independent of contrast and threshold), and
// - events no side explains, next to each other (structure, not noise), arrived near its
//   polygon (within kNearScale of its size about its centre): at least kMinUnexplainedShare of
//   what the side should have drawn. A side hidden by an occluder is silent too, but then its
//   edge fires nowhere in view.
// It must stay so for kPersistChecks snapshots over kPersistS of event time with no snapshot in
// between judging it to fire (snapshots where it did not move enough neither count nor clear;
// leaving the view clears): in a fast flip the estimate lags a few degrees and a side's events
// fall briefly outside its band, a wrong pose stays. Snapshots are taken at quality checks at
// least kSnapshotS apart (a noisy sensor checks every few ms, over which a slow side moves too
// little to be judged).
#include <dvs_line_tracker/segment_attribution.h>

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace dvs_line_tracker
{
class SilentSideCheck
{
public:
  /// `polygons`: the map's polygons as segment indices (the sides compared with each other);
  /// empty: all `num_segments` segments are one group. `ratio`: see above (0: off).
  SilentSideCheck(int num_segments, const std::vector<std::vector<int>>& polygons, double ratio);

  /// Count one event attributed to segment `i`.
  void countAttributed(int i)
  {
    if (i >= 0 && i < num_segments_)
      ++events_[i];
  }
  /// Count one event at ideal pixel `p` that no side explains and that lies next to others
  /// (structure), given the projections of now: near which polygons it is. Allocates nothing.
  void countUnexplained(const Eigen::Vector2d& p, const std::vector<ProjectedSegment>& projected);
  /// At a quality check at event time `t_ns`, with the projections of now: "" or why a side is
  /// silent.
  std::string check(const std::vector<ProjectedSegment>& projected, int64_t t_ns);
  /// A new track: everything forgotten.
  void restart();

  /// The span compared: the projections this many snapshots ago and now; a snapshot is taken
  /// at a check at least kSnapshotS of event time after the last.
  static constexpr int kSpanChecks = 8;
  static constexpr double kSnapshotS = 0.01;
  /// A side is judged once it moved this far (px along its normal, net over the span) and its
  /// polygon's density would have drawn at least kMinExpectedEvents to it ...
  static constexpr double kMinSweepPx = 1.0;
  static constexpr double kMinExpectedEvents = 50.0;
  /// ... against a reference side that moved at least kMinReferenceSweepPx and fired at least
  /// kMinReferenceEvents over the span.
  static constexpr double kMinReferenceSweepPx = 1.0;
  static constexpr double kMinReferenceEvents = 20.0;
  /// "Near its polygon": inside the polygon scaled by this about the mean of its visible ends.
  static constexpr double kNearScale = 1.5;
  static constexpr double kMinUnexplainedShare = 0.5;
  /// Snapshots, and event time, a side must be judged silent.
  static constexpr int kPersistChecks = 8;
  static constexpr double kPersistS = 0.1;

private:
  struct Snapshot
  {
    ProjectedSegment projected;  ///< (not visible until a snapshot is taken)
    uint64_t events = 0;         ///< the segment's attributed events counted until then
    uint64_t unexplained = 0;    ///< unexplained structure near its polygon counted until then
    double swept = 0;            ///< the area it swept snapshot by snapshot until then (px^2)
  };
  /// Inside polygon `g` scaled by kNearScale about its centre (projections of now).
  bool near(int g, const Eigen::Vector2d& p, const std::vector<ProjectedSegment>& projected) const;

  int num_segments_;
  double ratio_;
  std::vector<std::vector<int>> groups_;
  std::vector<Eigen::Vector2d> centres_;  ///< per group: the mean of its visible sides' ends at the last snapshot
  std::vector<char> have_centre_;
  std::vector<uint64_t> events_;       ///< attributed events per segment since the restart
  std::vector<uint64_t> unexplained_;  ///< per segment: unexplained structure near its polygon since the restart
  std::vector<double> swept_;          ///< area swept snapshot by snapshot per segment since the restart (px^2)
  std::vector<int> silent_checks_;     ///< snapshots in a row the segment was judged silent
  std::vector<int64_t> silent_since_ns_;  ///< since when (the first of those snapshots)
  std::vector<Snapshot> ring_;         ///< kSpanChecks snapshots per segment (segment-major)
  std::vector<int64_t> snapshot_ns_;   ///< per ring slot: when its snapshots were taken
  int head_ = 0;                       ///< the ring's oldest snapshot
  int checks_ = 0;                     ///< snapshots taken since the restart (up to kSpanChecks)
  int64_t last_snapshot_ns_ = 0;
  /// Per snapshot: each side's net sweep, summed sweep, events and unexplained structure near
  /// its polygon over the span.
  std::vector<double> swept_px2_, summed_px2_, span_events_, span_unexplained_;
};

/// The area (px^2) a segment swept from `before` to `now` along its normal, over its visible
/// length: both ends' normal displacements (a line turning about an inner point sweeps two
/// triangles).
double sweptArea(const ProjectedSegment& before, const ProjectedSegment& now);
}  // namespace dvs_line_tracker
