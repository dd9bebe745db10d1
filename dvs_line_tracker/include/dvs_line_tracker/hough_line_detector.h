#pragma once
// Line-segment detection for the initialisation (thesis 4.2.1): the most recent events are
// voted into a Hough space (7.5 deg x 2.5 px bins); every bin over the threshold is a line
// candidate (not only local maxima, thesis Fig. 4.2); the events near a candidate (looked up in a
// radius index of the window, line_point_index.h) are sorted along it and split into segments at
// gaps; short or sparse segments are dropped. By default (remove_found_votes) a segment found
// takes its events' votes out of a copy of the accumulator for the rest of the detection
// (progressive Hough), so the other bins over the threshold along the same edge are no
// candidates any more: about 9x faster than splitting every candidate (the full Hough, which
// the initialiser falls back on when the progressive segments give no pose: under background
// noise a noise event explained by a wrong segment no longer votes for the side; BENCHMARKS.md).
#include <dvs_line_tracker/line_point_index.h>
#include <dvs_line_tracker/neighbour_activity.h>

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <vector>

namespace dvs_line_tracker
{
struct HoughParams
{
  double angle_bin_deg = 7.5;           ///< angular bin size (thesis: 7.5 deg -> 24 bins over 180 deg)
  double radius_bin_px = 2.5;           ///< radial bin size (thesis: 2.5 px)
  int vote_threshold = 25;              ///< a bin with at least this many votes is a line candidate
  double attribution_distance_px = 2.0; ///< events within this distance belong to a candidate line
  double max_gap_px = 15.0;             ///< a larger gap between neighbouring events splits a segment
  double min_segment_length_px = 20.0;  ///< shorter segments are dropped
  int min_segment_events = 25;          ///< segments with fewer events are dropped
  int window_events = 1500;             ///< the Hough space holds the votes of this many latest events
  bool unique_pixels = false;           ///< a pixel already in the window does not vote again
  bool neighbour_filter = true;         ///< vote only for events with 8-neighbour events shortly before
  int neighbour_filter_min = 2;         ///< how many of the 8 neighbours must have fired
  int neighbour_filter_events = 500;    ///< "shortly before" = among the last this many events (adapts to the event rate)
  bool neighbour_same_polarity = false; ///< only neighbours of the event's polarity count (slow, noisy scenes; see BENCHMARKS.md)
  int max_candidates = 150;             ///< candidates examined per detection, most votes first
  int max_segments = 40;                ///< longest segments kept per detection
  int evidence_events = 0;              ///< voted positions kept for validation beyond the window (0: the window)
  /// Events this much older (event time) than the latest event stop voting and are no longer
  /// evidence (0: no limit): a slow scene's window otherwise still holds what the camera saw
  /// seconds before, e.g. screen_sim's alignment grid, whose rows of dots made a "square".
  double max_event_age_s = 3.0;
  bool remove_found_votes = true;       ///< progressive Hough: a found segment's points stop voting for the rest of the detection (faster, see BENCHMARKS.md)
};

/// A 2D segment in ideal (undistorted) pixel coordinates.
struct ImageSegment
{
  Eigen::Vector2d p0 = Eigen::Vector2d::Zero();
  Eigen::Vector2d p1 = Eigen::Vector2d::Zero();
  int num_events = 0;
  double length() const { return (p1 - p0).norm(); }
  Eigen::Vector2d direction() const { return (p1 - p0).normalized(); }
};

/// A line x cos(theta) + y sin(theta) = r in ideal pixel coordinates (origin top-left).
struct ImageLine
{
  double theta = 0.0;  ///< rad
  double r = 0.0;      ///< px
  Eigen::Vector2d normal() const { return {std::cos(theta), std::sin(theta)}; }
  double distance(const Eigen::Vector2d& p) const { return p.dot(normal()) - r; }
};

/// Total-least-squares line through points (needs >= 2 distinct points).
ImageLine fitLine(const std::vector<Eigen::Vector2d>& points);

/// Split the points near `line` (orthogonal distance <= params.attribution_distance_px) into
/// segments: sorted along the line, split at gaps > max_gap_px, kept when >= min length and
/// >= min events; each kept segment is refitted and its endpoints are the extreme events
/// projected onto the refitted line.
std::vector<ImageSegment> splitIntoSegments(const std::vector<Eigen::Vector2d>& points, const ImageLine& line,
                                            const HoughParams& params);

class HoughLineDetector
{
public:
  /// `width`, `height`: sensor size in pixels (the Hough space covers the image, or the
  /// undistorted image when `ideal_radius_px` (the largest distance of an ideal pixel from the
  /// image centre) is larger).
  HoughLineDetector(int width, int height, const HoughParams& params = HoughParams(), double ideal_radius_px = 0);

  void reset();
  /// One event: `x_ideal`, `y_ideal` its undistorted position, `sx`, `sy` its sensor pixel
  /// (for the neighbour filter), `t_ns` its time. Returns true when it was voted.
  bool addEvent(float x_ideal, float y_ideal, int sx, int sy, int64_t t_ns, bool on = false);

  int numAngleBins() const { return num_theta_; }
  int numRadiusBins() const { return num_r_; }
  int votes(int angle_bin, int radius_bin) const { return acc_[angle_bin * num_r_ + radius_bin]; }
  /// The bin's votes from events none of the last progressive detection's segments explained
  /// (all its votes before any progressive detection).
  int unexplainedVotes(int angle_bin, int radius_bin) const
  {
    return fresh_votes_.empty() ? votes(angle_bin, radius_bin) : fresh_votes_[angle_bin * num_r_ + radius_bin];
  }
  int numWindowEvents() const { return window_count_; }
  /// Line through the centre of a bin.
  ImageLine binLine(int angle_bin, int radius_bin) const;
  /// All bins with votes >= threshold, as (angle bin, radius bin), most votes first.
  std::vector<std::pair<int, int>> candidateBins() const;

  /// The positions currently voted (the window), oldest first.
  std::vector<Eigen::Vector2d> windowPoints() const;
  /// Time (ns) of the oldest of the latest `k` voted events still in the window (all of them
  /// when fewer); 0 when the window is empty.
  int64_t timeOfLatest(int k) const;
  /// The latest `evidence_events` voted positions (at least the window), oldest first.
  std::vector<Eigen::Vector2d> evidencePoints() const;

  /// Which candidate bins a detection splits into segments.
  enum class Pass
  {
    kProgressive,  ///< most votes first; a found segment's points stop voting for the rest
    kEveryBin,     ///< every candidate bin (the full Hough, thesis Fig. 4.2)
    /// Every candidate bin that has no fewer votes than its two radius neighbours at the same
    /// angle (radiusPeak): the peaks across a line's radius. An edge that moved while the window
    /// filled is a band of events several bins wide at its angle; the full Hough fitted a line to
    /// every bin across the band (about 130 distinct lines per detection on the DVS128 flip), the
    /// peaks fit one or two of them (BENCHMARKS.md, twenty-fourth session).
    kRadiusPeaks
  };

  /// Segments found from all candidate bins, duplicates removed, longest first.
  std::vector<ImageSegment> detectSegments() const { return detectSegments(params_.remove_found_votes); }
  /// The same, progressive (found segments' points stop voting) or not, whatever the parameters say.
  std::vector<ImageSegment> detectSegments(bool progressive) const
  {
    return detectSegments(progressive ? Pass::kProgressive : Pass::kEveryBin);
  }
  std::vector<ImageSegment> detectSegments(Pass pass) const;

  const HoughParams& params() const { return params_; }

  /// Whether the bin has no fewer votes than its radius neighbours at the same angle.
  bool radiusPeak(int angle_bin, int radius_bin) const;

private:
  /// The radius bin of the point's Hough curve at each angle (-1: outside the accumulator).
  void curveBins(float x, float y, int32_t* bins) const;
  /// Adds `increment` to the bins `bins` (curveBins()) in `acc`.
  void vote(const int32_t* bins, int increment, std::vector<int>& acc) const;
  /// The curve bins of the event in window slot `slot` (computed once, when it was voted).
  int32_t* slotBins(int slot) { return window_bins_.data() + static_cast<size_t>(slot) * num_theta_; }
  const int32_t* slotBins(int slot) const { return window_bins_.data() + static_cast<size_t>(slot) * num_theta_; }

  HoughParams params_;
  int width_, height_;
  int num_theta_, num_r_;
  double r_max_;
  double cx_, cy_;  // Hough origin (image centre)
  std::vector<double> cos_, sin_;
  std::vector<int> acc_;
  /// Drops the window's and the evidence's events older than `t_ns` - max_event_age_s.
  void expireBefore(int64_t t_ns);

  std::vector<Eigen::Vector2f> window_;  // ring buffer of voted positions
  std::vector<int32_t> window_pixel_;    // their sensor pixel index (-1: none)
  std::vector<int64_t> window_t_;        // their times (ns)
  std::vector<int32_t> window_bins_;     // their curves' radius bins, num_theta_ per slot
  std::vector<uint8_t> in_window_;       // per sensor pixel: already voting
  int window_head_ = 0, window_count_ = 0;
  std::vector<Eigen::Vector2f> evidence_;  // ring buffer of the latest voted positions
  std::vector<int64_t> evidence_t_;        // their times (ns)
  int evidence_head_ = 0, evidence_count_ = 0;
  int64_t max_age_ns_ = 0;                 // max_event_age_s (0: no limit)
  NeighbourActivity activity_;  // the neighbour filter
  // detectSegments' scratch memory, reused between detections: the index of the window's
  // points, the votes not explained by a found segment yet, which points are explained.
  mutable LinePointIndex index_{1, 1.0, 1.0, Eigen::Vector2d::Zero()};
  mutable std::vector<int> fresh_votes_;
  mutable std::vector<char> explained_;
  // What a detection found per candidate bin, kept for the next detection on the same window
  // (the initialiser's full-Hough fallback runs on the window the progressive pass just saw):
  // a bin's line (fitted, gated, refitted) and that line's segments do not depend on the pass.
  struct BinResult
  {
    enum State : uint8_t
    {
      kUnknown,
      kRejected,  ///< too little support
      kLine
    } state = kUnknown;
    bool split = false;  ///< `segments` holds the line's segments
    ImageLine line;
    std::vector<ImageSegment> segments;
  };
  /// Whenever the window changes (an event voted or expired, a reset), so that the detection
  /// knows whether its scratch still describes the window.
  void windowChanged() { ++window_generation_; }
  uint64_t window_generation_ = 0;
  mutable uint64_t detected_generation_ = ~uint64_t{0};
  /// The detector the scratch was made by: a copy's index points into the original's points.
  mutable const HoughLineDetector* detected_by_ = nullptr;
  mutable std::vector<Eigen::Vector2d> detected_points_;
  mutable int detected_start_ = 0;  ///< the window slot of detected_points_[0]
  mutable std::vector<std::pair<int, int>> detected_bins_;
  mutable std::vector<BinResult> bin_results_;
};
}  // namespace dvs_line_tracker
