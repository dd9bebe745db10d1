#pragma once
// (Re-)initialisation (thesis 4.2.1): the events vote in a Hough accumulator over a sliding
// window (its event counts and gaps scaled to the sensor size); every few hundred voted events
// segments are detected (the progressive Hough, and when its segments give no pose the full
// Hough on the same window), filtered (not along the image border), assembled into image
// polygons with the map's side counts (corners may lie outside the image: partial views; then
// from segments split at junctions; then, when none started tracking, polygons with one side
// out of view, and last such polygons with one inner side bridged between the inner ends of
// its neighbours; poses of those, and every pose with a map of several polygons, must also
// explain most of the window's events), and
// each polygon's corners give one pose hypothesis per map polygon of that side count
// (pose_initializer.h), refined on the window's events near the projected map
// (point-to-line), validated (every visible map side covered by recent voted events, a quiet
// inside), ranked by the evidence the projected map explains (ambiguous rankings wait), and
// confirmed by an earlier agreeing detection. The confirmed pose is offered to the caller,
// which starts tracking from it or declines (too little of the map in view).
#include <dvs_driver/event.h>
#include <dvs_line_tracker/estimator_state.h>
#include <dvs_line_tracker/hough_line_detector.h>
#include <dvs_line_tracker/point_grid.h>
#include <dvs_line_tracker/polygon_search.h>
#include <dvs_line_tracker/tracker_params.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace dvs_line_tracker
{
/// What the initialiser did with its detection attempts (why there is no pose yet).
struct InitializerStats
{
  uint64_t events = 0;                ///< events offered while not tracking
  uint64_t events_voted = 0;          ///< of those, the ones that passed the neighbour filter and voted in the Hough space
  uint64_t attempts = 0;              ///< detections run on the Hough window
  uint64_t full_hough_attempts = 0;   ///< attempts that also ran the full Hough (init_full_hough_fallback)
  uint64_t wide_turn_attempts = 0;    ///< attempts that also searched polygons with turns only the wide bounds admit (polygon_wide_*_angle_deg)
  uint64_t segments = 0;              ///< segments found (summed over attempts)
  uint64_t polygons = 0;              ///< image polygons assembled
  uint64_t cut_by_border = 0;         ///< polygons with a corner at or beyond the image border (partial views; still tried)
  uint64_t pose_failed = 0;           ///< polygons whose corners gave no consistent pose
  uint64_t coverage_failed = 0;       ///< poses whose projected map was not backed by window events
  uint64_t unexplained = 0;           ///< poses that left too many recent events unexplained (init_min_explained; open polygons, one side out of view, and maps of several polygons: most)
  uint64_t too_oblique = 0;           ///< poses seeing their polygon more than init_max_view_angle_deg off its normal
  uint64_t ambiguous = 0;             ///< the map did not decide: two map polygons explained the events about equally well, one rejected for its sides' coverage explained clearly more of them, or a symmetric polygon's rotations were about equally upright, or the camera rolled too fast for the map's up to pick one
  uint64_t unconfirmed = 0;           ///< valid detections waiting for an agreeing one
  uint64_t declined = 0;              ///< confirmed poses the tracker declined (too little map in view)
  uint64_t accepted = 0;
  uint64_t prior_attempts = 0;        ///< after a loss: the last tracked pose refined on the window's events
  uint64_t prior_accepted = 0;        ///< re-acquisitions from that prior
  /// One JSON object of the counters (keys as the fields).
  std::string json() const;
  /// Why there is no pose yet, in one sentence for a user: the stage that stopped every
  /// detection (no events, too few events through the neighbour filter, no polygon of the map's
  /// side counts, none backed by events, ...) and the counters behind it.
  std::string noPoseReason() const;
};

class TrackerInitializer
{
public:
  TrackerInitializer(const TrackingGeometry& geometry, const LineTrackerParams& params);

  /// Starts tracking from a confirmed pose; false: declined (the detection window restarts).
  using StartTracking = std::function<bool(const Pose& pose)>;

  /// Feed one event (ideal pixel `p`, the raw event). Returns true when a detection was
  /// confirmed and `start` accepted it.
  bool addEvent(const Eigen::Vector2d& p, const dvs_driver::Event& e, const StartTracking& start);

  /// After a loss or a declined start: empty the window, forget unconfirmed detections.
  void restart();
  /// After a loss: the last tracked pose. For `reacquire_prior_s` of event time every detection
  /// attempt first refines it on the window's events and validates it like a detection (every
  /// visible map side covered), so that the track comes back even when no whole polygon is in
  /// view; the prior follows the refined pose while the evidence holds.
  void setPrior(const Pose& pose, int64_t t_ns);
  /// Everything back to the constructed state.
  void reset();

  /// The image polygon of the last accepted detection (ideal pixels).
  const ImagePolygon& lastPolygon() const { return last_polygon_; }
  const InitializerStats& stats() const { return stats_; }
  /// The Hough detector's parameters, scaled to the sensor (init_scale_with_sensor).
  const HoughParams& houghParams() const { return hough_.params(); }
  /// A neighbour-test horizon given for a 128x128 sensor, scaled to this one as the Hough
  /// filter's (init_scale_with_sensor: by the pixel count).
  int scaledNeighbourHorizon(int events_128) const;
  /// Time (ns) of the oldest event the initial pose was refined on (init_refine_events of the
  /// Hough window; the whole window without refinement): the pose fits the events since.
  int64_t refineWindowStartNs() const { return hough_.timeOfLatest(refine_events_ > 0 ? refine_events_ : hough_.numWindowEvents()); }

private:
  bool tryInitialize(const StartTracking& start);
  bool tryPrior(const StartTracking& start);
  bool alongBorder(const ImageSegment& segment) const;
  /// A later detection agreeing with `pose` (position / distance and angle bounds) is needed;
  /// when none of the agreeing detections is `strong` (covered init_min_coverage), one more.
  /// `roll_rate_deg_s` (optional): the fastest roll (about the optical axis) from an agreeing
  /// earlier detection to this one.
  bool confirmed(const Pose& pose, int extra = 0, bool strong = true, double* roll_rate_deg_s = nullptr);
  /// The voted positions a detection attempt works on, copied once per attempt.
  struct RecentEvents
  {
    std::vector<Eigen::Vector2d> refine;    ///< the latest init_refine_events (scaled) of the window
    std::vector<Eigen::Vector2d> window;    ///< the Hough window
    std::vector<Eigen::Vector2d> evidence;  ///< init_evidence_windows windows
    /// The window and the evidence bucketed (sideCoverage), built at the first use: most
    /// attempts find no polygon to validate.
    const PointGrid& windowGrid() const
    {
      buildGrids();
      return window_grid;
    }
    const PointGrid& evidenceGrid() const
    {
      buildGrids();
      return evidence_grid;
    }

  private:
    void buildGrids() const
    {
      if (grids_built)
        return;
      window_grid.reset(window);
      evidence_grid.reset(evidence);
      grids_built = true;
    }
    mutable PointGrid window_grid{8.0}, evidence_grid{8.0};
    mutable bool grids_built = false;
  };
  RecentEvents recentEvents() const;
  /// What became of one image polygon: try the next, stop this attempt (a valid detection
  /// awaits confirmation), or tracking started.
  enum class Outcome
  {
    kNext,
    kStop,
    kStarted
  };
  /// Hypotheses from `polygon` (one per map polygon of its side count), validated, ranked and
  /// confirmed; starts tracking from the winner.
  /// `extra_confirmations`: agreeing detections needed beyond the usual (inferred sides).
  Outcome tryPolygon(const ImagePolygon& polygon, const RecentEvents& recent, const StartTracking& start,
                     int extra_confirmations = 0);
  /// The polygons (closed, then open, then bridged) of `segments` under the turn bounds of
  /// `search`, each tried as a hypothesis.
  Outcome trySegments(const std::vector<ImageSegment>& segments, const RecentEvents& recent,
                      const StartTracking& start, const PolygonSearchParams& search);
  /// The Hough window's segments from one pass (progressive, every bin, radius peaks), those
  /// along the image border removed.
  std::vector<ImageSegment> detectSegments(HoughLineDetector::Pass pass);
  /// The wide turn bounds reach beyond polygon_min/max_angle_deg.
  bool wideTurnsEnabled() const;
  Pose refineWithWindowEvents(const Pose& initial, const RecentEvents& recent) const;
  /// The same, attributing the events at `distance_px` instead of the Hough's distance.
  Pose refineWithWindowEvents(const Pose& initial, const RecentEvents& recent, double distance_px) const;
  /// The prior refined on the window events from its capture range (reacquire_capture_px) down,
  /// halving it, to the Hough's attribution distance.
  Pose refinePrior(const RecentEvents& recent) const;
  struct Coverage
  {
    double min_fraction = 0;   ///< smallest covered fraction over the visible map segments
    double covered_px = 0;     ///< covered length summed over them (the evidence the pose explains)
  };
  /// Per visible map segment, the fraction of 3 px cells along it holding a recent voted event
  /// within the attribution distance (min_fraction 0 when fewer than min_visible_segments are
  /// visible, a polygon's inside is busy, or the strips beside the sides are nearly as covered:
  /// init_max_surrounding_coverage).
  Coverage sideCoverage(const Pose& pose, const RecentEvents& recent) const;
  /// A hypothesis is valid when covered at least kWeakCoverageRatio of init_min_coverage (weak
  /// below init_min_coverage itself).
  bool valid(const Coverage& coverage) const;
  /// With several map polygons: the candidate's polygon rotated (InitialPose::rotations) when
  /// one rotation explains clearly more events than every other (then its up_margin is
  /// infinite: the map, not its up, decided).
  void pickRotationByEvidence(InitialPose& candidate, Coverage& coverage, const RecentEvents& recent) const;
  /// The camera pose that sees the map as `pose` does after the map symmetry `symmetry`.
  static Pose symmetric(const Eigen::Isometry3d& symmetry, const Pose& pose);
  /// After a loss: `winner` lies far from the prior while another of `hypotheses` (the map
  /// polygons' poses for one image polygon) lies much closer to it.
  bool priorContradicts(const Pose& winner, const std::vector<Pose>& hypotheses) const;
  /// The same hypothesis (sameHypothesis), or one of its symmetric poses (lineMapSymmetries).
  bool sameUpToSymmetry(const Pose& a, const Pose& b) const;
  /// A pose the events decided (infinite up_margin): replaced by its most upright symmetric
  /// pose (lineMapSymmetries), up_margin its lead over the next; unchanged without symmetries.
  void uprightAmongSymmetric(InitialPose& init) const;
  /// Fraction of the Hough window's events within the attribution distance of a projected map
  /// segment (the evidence `pose` explains, whatever it leaves out).
  double explainedFraction(const Pose& pose, const RecentEvents& recent) const;
  /// Angle (deg, 0-90) between the polygon's normal and the line from its corners' centroid to
  /// the camera.
  static double viewAngleDeg(const Pose& pose, const MapPolygon& polygon);
  /// RMS distance (px) of the refinement events within the window's attribution distance of a
  /// projected map segment (beside it, not beyond its ends) to the nearest such segment;
  /// infinite when none is.
  double refineResidualPx(const Pose& pose, const RecentEvents& recent) const;
  /// The map's segments projected at `pose` (TrackingGeometry::project, ideal pixels), one per
  /// map segment, visible when in front of the camera (not clipped to the image).
  std::vector<ProjectedSegment> projectedMap(const Pose& pose) const;

  const TrackingGeometry& geometry_;
  const LineTrackerParams& params_;
  double scale_;                   ///< sensor scale of the event counts and gaps (1 for 128x128)
  HoughLineDetector hough_;
  int check_interval_, min_events_, refine_events_;
  AttributionParams window_attribution_;  ///< the window events' attribution (hough_attribution_distance_px)
  std::vector<int> side_counts_;   ///< distinct side counts of the map's polygons
  std::vector<Eigen::Isometry3d> symmetries_;  ///< lineMapSymmetries of the map
  std::vector<Eigen::Vector3d> map_points_;    ///< every map segment's endpoints (the map's up score)
  int voted_since_check_ = 0;
  int64_t last_check_ns_ = std::numeric_limits<int64_t>::min() / 2;
  struct Detection
  {
    Pose pose;
    bool strong = true;  ///< covered init_min_coverage (not only its kWeakCoverageRatio)
    int64_t t_ns = 0;    ///< when it was detected
  };
  std::vector<Detection> recent_;  ///< the last detections awaiting confirmation
  ImagePolygon last_polygon_;
  InitializerStats stats_;
  bool have_prior_ = false;
  Pose prior_;
  int64_t prior_ns_ = 0;
};
}  // namespace dvs_line_tracker
