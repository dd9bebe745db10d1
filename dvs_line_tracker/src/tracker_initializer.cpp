#include <dvs_line_tracker/tracker_initializer.h>

#include <dvs_line_tracker/pose_initializer.h>

#include <algorithm>
#include <cmath>

namespace dvs_line_tracker
{
namespace
{
/// Polygons whose sides' gaps to their corners exceed this fraction of the perimeter need one
/// more confirmation.
constexpr double kInferredOutlineRatio = 0.25;

/// Open polygons' outer ends must lie this fraction of the image size from its border (or
/// beyond): with a distorted lens the sensor's border is curved in the ideal image.
constexpr double kOpenBorderRatio = 0.06;

/// Open polygons' poses must explain this fraction of the Hough window's events.
constexpr double kOpenMinExplained = 0.5;

/// A detection covered this fraction of init_min_coverage is weak: it confirms or is confirmed
/// by a detection covered init_min_coverage, never starts tracking with weak ones alone.
constexpr double kWeakCoverageRatio = 0.75;

/// The planar-PnP twin replaces the corners' pose when it explains this much more evidence, or,
/// explaining about as much (within this factor either way), when its point-to-line RMS on the
/// refinement events is below kTwinResidualRatio of the corners' pose's.
constexpr double kTwinMargin = 1.1;
constexpr double kTwinResidualRatio = 0.99;

/// The coverage test also looks at the strips this many attribution distances beside each side
/// (init_max_surrounding_coverage).
constexpr double kSurroundingShift = 3.0;

/// Closed polygons with a side bridged between two sides running out of view need this many more
/// agreeing detections.
constexpr int kBridgedClosedConfirmations = 2;

/// A second hypothesis explaining this fraction of the best one's evidence makes it ambiguous.
constexpr double kAmbiguityRatio = 0.85;

/// With several map polygons, a hypothesis rejected for its sides' coverage that explains this
/// much more of the window's events (as a fraction of them) than the winner makes it ambiguous.
constexpr double kRejectedExplainedMargin = 0.1;

/// After a loss, a re-initialisation further than kPriorFarRatio x the distance from the pose
/// tracked before, while another map polygon's hypothesis lies less than kPriorCloserRatio as
/// far from it, waits (hand-held motion moved the camera by 34 % of the distance in the 0.5 s
/// after a loss; a pair's squares were 135 % apart).
constexpr double kPriorFarRatio = 0.6;
constexpr double kPriorCloserRatio = 0.5;

/// Polygons collected from the split segments, of which the 8 whose sides meet best are tried:
/// the search finds the long unsplit segments' polygons first (joining neighbouring polygons'
/// collinear sides), and stopping at 8 left the pieces' polygons unsearched.
constexpr int kSearchPolygons = 32;

double sensorScale(const TrackingGeometry& g, const LineTrackerParams& p)
{
  return p.init_scale_with_sensor ? std::max(1.0, std::sqrt(static_cast<double>(g.width) * g.height) / 128.0) : 1.0;
}

int scaled(int count, double scale) { return std::max(1, static_cast<int>(std::lround(count * scale))); }

/// A neighbour test's horizon given for 128x128, at sensor scale `s`: by the pixel count (the
/// same events per pixel on every sensor).
int scaledHorizon(int events_128, double s) { return scaled(events_128, s * s); }

HoughParams scaledHough(const TrackingGeometry& g, const LineTrackerParams& p)
{
  const double s = sensorScale(g, p);
  HoughParams h = p.hough;
  h.window_events = scaled(h.window_events, s);
  h.vote_threshold = scaled(h.vote_threshold, s);
  // The filter's horizon scales with the pixel count: what lets a noise event through is the
  // chance that two of its neighbours fired within the horizon, about the horizon's events per
  // pixel squared, kept at the 128x128 sensor's (with sqrt(pixels) scaling a 640x480 sensor's
  // horizon held 4.3x fewer events per pixel, shorter than the time a slow edge takes to cross
  // neighbouring pixels, and the filter rejected the edges too).
  h.neighbour_filter_events = scaledHorizon(h.neighbour_filter_events, s);
  h.max_gap_px *= s;
  h.evidence_events = static_cast<int>(std::lround(h.window_events * p.init_evidence_windows));
  return h;
}
}  // namespace

std::string InitializerStats::json() const
{
  const std::pair<const char*, uint64_t> fields[] = {
      {"events", events},             {"events_voted", events_voted},
      {"attempts", attempts},         {"full_hough_attempts", full_hough_attempts},
      {"wide_turn_attempts", wide_turn_attempts}, {"segments", segments},         {"polygons", polygons},
      {"cut_by_border", cut_by_border}, {"pose_failed", pose_failed}, {"coverage_failed", coverage_failed}, {"unexplained", unexplained},
      {"too_oblique", too_oblique},   {"ambiguous", ambiguous},       {"unconfirmed", unconfirmed},   {"declined", declined},
      {"accepted", accepted},         {"prior_attempts", prior_attempts}, {"prior_accepted", prior_accepted}};
  std::string out = "{";
  for (const auto& f : fields)
    out += std::string(out.size() > 1 ? ", " : "") + "\"" + f.first + "\": " + std::to_string(f.second);
  return out + "}";
}

std::string InitializerStats::noPoseReason() const
{
  if (events == 0)
    return "no events reached the initialiser";
  const std::string voted = std::to_string(events_voted) + " of " + std::to_string(events) + " events (" +
                            std::to_string(static_cast<int>(std::lround(100.0 * events_voted / events))) +
                            " %) passed the neighbour filter";
  // Below a tenth of the events, or too few for a single detection: most events are isolated
  // (noise) and the map's edges fire too sparsely to stand out (8 of the 12 scenes of the
  // 192-scene sweep that never start vote 3-9 % of their events).
  if (attempts == 0 || events_voted * 10 < events)
    return voted + " and " + std::to_string(attempts) +
           " detection attempts ran: most events are isolated (noise) and the map's edges fire too sparsely to "
           "stand out (slow motion, low contrast or a far target: move the camera, or come closer; in heavy background "
           "activity the parameters init_neighbour_same_polarity: true and init_neighbour_filter_events: 1500 start "
           "more such scenes)";
  std::string why;
  if (polygons == 0)
    why = "no image polygon with the map's side counts among the " + std::to_string(segments) +
          " segments found (is the map right and its target whole, or all but one side, in view?)";
  else
    why = std::to_string(polygons) + " image polygons: " + std::to_string(pose_failed) + " gave no pose, " +
          std::to_string(coverage_failed) + " were not backed by events along every visible map edge, " +
          std::to_string(unexplained) + " left most events unexplained, " + std::to_string(too_oblique) +
          " were seen too far off the polygon's normal, " + std::to_string(ambiguous) +
          " ambiguous, " + std::to_string(unconfirmed) + " unconfirmed (is the map right, the target in view and moving?)";
  return voted + ", " + std::to_string(attempts) + " detection attempts: " + why;
}

TrackerInitializer::TrackerInitializer(const TrackingGeometry& geometry, const LineTrackerParams& params)
  : geometry_(geometry)
  , params_(params)
  , scale_(sensorScale(geometry, params))
  , hough_(geometry.width, geometry.height, scaledHough(geometry, params), geometry.ideal_radius_px)
  , check_interval_(scaled(params.init_check_interval, scale_))
  , min_events_(scaled(params.init_min_events, scale_))
  , refine_events_(params.init_refine_events > 0 ? scaled(params.init_refine_events, scale_) : 0)
  , symmetries_(lineMapSymmetries(geometry.map))
{
  // The window's events span the window's time, over which an edge moves: they are attributed
  // at the Hough's distance, not at the tracker's (which attributes each event at its time).
  window_attribution_ = params.attribution;
  window_attribution_.max_orthogonal_px = params.hough.attribution_distance_px;
  for (const auto& s : geometry.map.segments)
  {
    map_points_.push_back(s.p0_world);
    map_points_.push_back(s.p1_world);
  }
  for (const auto& poly : geometry.map.polygons)
    if (std::find(side_counts_.begin(), side_counts_.end(), static_cast<int>(poly.segment_ids.size())) ==
        side_counts_.end())
      side_counts_.push_back(static_cast<int>(poly.segment_ids.size()));
}

int TrackerInitializer::scaledNeighbourHorizon(int events_128) const { return scaledHorizon(events_128, scale_); }

void TrackerInitializer::restart()
{
  recent_.clear();
  hough_.reset();
  voted_since_check_ = 0;
}

void TrackerInitializer::reset()
{
  restart();
  last_check_ns_ = std::numeric_limits<int64_t>::min() / 2;
  last_polygon_ = ImagePolygon();
  stats_ = InitializerStats();
  have_prior_ = false;
}

void TrackerInitializer::setPrior(const Pose& pose, int64_t t_ns)
{
  have_prior_ = params_.reacquire_prior_s > 0 && pose.allFinite();
  prior_ = pose;
  prior_ns_ = t_ns;
}

bool TrackerInitializer::tryPrior(const StartTracking& start)
{
  if (!have_prior_ || refine_events_ <= 0)
    return false;
  if (last_check_ns_ - prior_ns_ > static_cast<int64_t>(params_.reacquire_prior_s * 1e9))
  {
    have_prior_ = false;
    return false;
  }
  ++stats_.prior_attempts;
  const RecentEvents recent = recentEvents();
  const Pose pose = refinePrior(recent);
  if (sideCoverage(pose, recent).min_fraction < params_.init_min_coverage)
    return false;
  prior_ = pose;  // follow the camera while the evidence holds
  if (!confirmed(pose))
  {
    ++stats_.unconfirmed;
    return false;
  }
  recent_.clear();
  if (!start(pose))
  {
    ++stats_.declined;
    return false;
  }
  ++stats_.prior_accepted;
  have_prior_ = false;
  return true;
}

bool TrackerInitializer::addEvent(const Eigen::Vector2d& p, const dvs_driver::Event& e, const StartTracking& start)
{
  ++stats_.events;
  if (!hough_.addEvent(static_cast<float>(p.x()), static_cast<float>(p.y()), e.x, e.y, e.t_ns, e.polarity != 0))
    return false;
  ++stats_.events_voted;
  ++voted_since_check_;
  if (hough_.numWindowEvents() < min_events_ || voted_since_check_ < check_interval_ ||
      e.t_ns - last_check_ns_ < static_cast<int64_t>(params_.init_min_check_period_s * 1e9))
    return false;
  voted_since_check_ = 0;
  last_check_ns_ = e.t_ns;
  return tryInitialize(start);
}

bool TrackerInitializer::alongBorder(const ImageSegment& sg) const
{
  // Segments along the image border are the borders of accumulated event bands (an edge that
  // leaves the image), not edges of the scene.
  const double m = params_.init_border_margin_px, w = geometry_.width - 1.0, h = geometry_.height - 1.0;
  auto near = [&](double a, double b, double border) { return std::abs(a - border) < m && std::abs(b - border) < m; };
  return near(sg.p0.x(), sg.p1.x(), 0.0) || near(sg.p0.x(), sg.p1.x(), w) || near(sg.p0.y(), sg.p1.y(), 0.0) ||
         near(sg.p0.y(), sg.p1.y(), h);
}

bool TrackerInitializer::confirmed(const Pose& pose, int extra, bool strong, double* roll_rate_deg_s)
{
  // Two detections in a row must agree (a false polygon from smeared or partial edges rarely
  // repeats itself consistently), and one of them must be strongly covered.
  if (roll_rate_deg_s)
    *roll_rate_deg_s = 0;
  if (params_.init_confirmations + extra <= 0)
    return strong;
  int agreeing = 0;
  bool any_strong = strong;
  for (const auto& earlier : recent_)
  {
    // A pair with a weak detection must agree twice as closely.
    const double bound = earlier.strong && strong ? 1.0 : 0.5;
    if (posesAgree(earlier.pose, pose, bound * params_.init_confirm_position_ratio, bound * params_.init_confirm_angle_deg))
    {
      ++agreeing;
      any_strong |= earlier.strong;
      if (roll_rate_deg_s && last_check_ns_ > earlier.t_ns)
        *roll_rate_deg_s =
            std::max(*roll_rate_deg_s, std::abs(rollRateDegS(earlier.pose, pose, (last_check_ns_ - earlier.t_ns) * 1e-9)));
    }
  }
  recent_.push_back({pose, strong, last_check_ns_});
  if (recent_.size() > 4)
    recent_.erase(recent_.begin());
  // Weak detections alone need one more agreeing detection (an edge moving along itself fires
  // little for as long as the motion lasts; three agreeing weak detections are no accident).
  return agreeing >= params_.init_confirmations + extra + (any_strong ? 0 : 1);
}

bool TrackerInitializer::tryInitialize(const StartTracking& start)
{
  if (tryPrior(start))
    return true;
  ++stats_.attempts;
  const RecentEvents recent = recentEvents();
  const bool progressive = params_.hough.remove_found_votes;
  std::vector<ImageSegment> segments =
      detectSegments(progressive ? HoughLineDetector::Pass::kProgressive : HoughLineDetector::Pass::kEveryBin);
  Outcome o = trySegments(segments, recent, start, params_.polygon);
  // Nothing to start from or to confirm: the full Hough finds what noise hid from the
  // progressive one (a noise event explained by a wrong segment no longer votes for the side),
  // from each angle's radius peaks (the bins across an edge's band fit the same edge).
  if (o == Outcome::kNext && progressive && params_.init_full_hough_fallback && hough_.numWindowEvents() > 0)
  {
    ++stats_.full_hough_attempts;
    segments = detectSegments(HoughLineDetector::Pass::kRadiusPeaks);
    o = trySegments(segments, recent, start, params_.polygon);
  }
  // Still nothing: the polygons only the wider turn bounds admit (a polygon seen at a steep
  // angle, close, through a wide lens turns by 30-35 deg at its far corners). They come last so
  // that they never displace a polygon of the usual bounds (ranked among those, slivers of
  // real clutter came first).
  if (o == Outcome::kNext && wideTurnsEnabled())
  {
    PolygonSearchParams wide = params_.polygon;
    wide.min_turn_angle_deg = params_.polygon_wide_min_angle_deg;
    wide.max_turn_angle_deg = params_.polygon_wide_max_angle_deg;
    wide.outside_min_turn_angle_deg = params_.polygon.min_turn_angle_deg;
    wide.outside_max_turn_angle_deg = params_.polygon.max_turn_angle_deg;
    ++stats_.wide_turn_attempts;
    o = trySegments(segments, recent, start, wide);
  }
  return o == Outcome::kStarted;
}

bool TrackerInitializer::wideTurnsEnabled() const
{
  return params_.polygon_wide_min_angle_deg < params_.polygon.min_turn_angle_deg ||
         params_.polygon_wide_max_angle_deg > params_.polygon.max_turn_angle_deg;
}

std::vector<ImageSegment> TrackerInitializer::detectSegments(HoughLineDetector::Pass pass)
{
  std::vector<ImageSegment> segments = hough_.detectSegments(pass);
  segments.erase(std::remove_if(segments.begin(), segments.end(),
                                [this](const ImageSegment& sg) { return alongBorder(sg); }),
                 segments.end());
  stats_.segments += segments.size();
  return segments;
}

TrackerInitializer::Outcome TrackerInitializer::trySegments(const std::vector<ImageSegment>& segments,
                                                            const RecentEvents& recent, const StartTracking& start,
                                                            const PolygonSearchParams& search)
{
  // The polygons of the detected segments first, then those that need a segment split where
  // another one meets it (collinear sides of neighbouring polygons detected as one segment).
  // Sides that reach the image border may meet beyond it (a corner out of view).
  const double border = std::max(params_.init_border_margin_px,
                                 kOpenBorderRatio * (std::max(geometry_.width, geometry_.height) - 1.0));
  const ImageView view{static_cast<double>(geometry_.width), static_cast<double>(geometry_.height), border};
  std::vector<ImagePolygon> polygons;
  for (int sides : side_counts_)
    for (ImagePolygon& polygon : findPolygons(segments, sides, search, 8, 0, view))
      polygons.push_back(std::move(polygon));
  const std::vector<ImageSegment> split = splitAtJunctions(segments, search);
  if (split.size() > segments.size())
    for (int sides : side_counts_)
      for (ImagePolygon& polygon : findPolygons(split, sides, search, 8, kSearchPolygons, view))
        if (std::none_of(polygons.begin(), polygons.end(), [&](const ImagePolygon& q) { return sameCorners(q, polygon); }))
          polygons.push_back(std::move(polygon));
  for (const ImagePolygon& polygon : polygons)
  {
    const Outcome o = tryPolygon(polygon, recent, start);
    if (o != Outcome::kNext)
      return o;
  }
  // When no whole polygon started tracking: polygons with one side out of view (a partial view
  // with a side beyond the border).
  // The open polygons of `searched` (with `first_bridge` >= 0: each using one of its bridges).
  auto tryOpenPolygons = [&](const std::vector<ImageSegment>& searched, int first_bridge) {
    for (int sides : side_counts_)
      for (const ImagePolygon& polygon : findOpenPolygons(searched, sides, search, geometry_.width,
                                                          geometry_.height, border, 8, first_bridge))
      {
        const Outcome o = tryPolygon(polygon, recent, start);
        if (o != Outcome::kNext)
          return o;
      }
    return Outcome::kNext;
  };
  Outcome o = tryOpenPolygons(split, -1);
  if (o != Outcome::kNext)
    return o;
  // Then open polygons with an inner side too weak to be detected (parallel to the motion),
  // bridged between the inner ends of its neighbours.
  const std::vector<ImageSegment> bridged =
      bridgeBorderSegments(split, search, geometry_.width, geometry_.height, border);
  if (bridged.size() > split.size())
    o = tryOpenPolygons(bridged, static_cast<int>(split.size()));
  if (o != Outcome::kNext)
    return o;
  // The whole polygons of `searched` not tried above, each confirmed by `extra` more detections.
  auto tryMoreClosedPolygons = [&](const std::vector<ImageSegment>& searched, int extra) {
    for (int sides : side_counts_)
      for (const ImagePolygon& polygon : findPolygons(searched, sides, search, 8, kSearchPolygons, view))
        if (std::none_of(polygons.begin(), polygons.end(), [&](const ImagePolygon& q) { return sameCorners(q, polygon); }))
        {
          const Outcome tried = tryPolygon(polygon, recent, start, extra);
          if (tried != Outcome::kNext)
            return tried;
        }
    return Outcome::kNext;
  };
  // Last, sides detected as two collinear pieces (the middle of a side moving along itself, or
  // of a low-contrast edge, fires little): whole polygons with such a side joined.
  const std::vector<ImageSegment> joined = joinCollinearSegments(segments);
  if (joined.size() > segments.size())
    o = tryMoreClosedPolygons(joined, 0);
  if (o != Outcome::kNext)
    return o;
  // And whole polygons with a side bridged between the inner ends of two sides running out of
  // view (a square at a steep angle close to a wide lens: its near side moves along itself and
  // is not detected, its far side is in view). The bridge is inferred, not seen, and bridges
  // between unrelated segments make closed polygons too: two more agreeing detections are needed
  // (with one more, a false start in the 192-scene sweep, scene 166).
  if (bridged.size() > split.size())
    o = tryMoreClosedPolygons(bridged, kBridgedClosedConfirmations);
  return o;
}

TrackerInitializer::Outcome TrackerInitializer::tryPolygon(const ImagePolygon& polygon, const RecentEvents& recent,
                                                           const StartTracking& start, int extra_confirmations)
{
  const double m = params_.init_border_margin_px, w = geometry_.width - 1.0, h = geometry_.height - 1.0;
  ++stats_.polygons;
  // Corners may lie outside the image (a partial view): the validation below then checks
  // the sides that are in view.
  for (const auto& c : polygon.corners)
    if (polygon.open || c.x() < m || c.y() < m || c.x() > w - m || c.y() > h - m)
    {
      ++stats_.cut_by_border;
      break;
    }
  // Each map polygon with this many sides is a hypothesis (several identical squares are
  // told apart by the rest of the map): valid when every visible map side is covered by
  // recent events (checking only the matched polygon's sides let wrong matches through:
  // 8 false initialisations in the sweep instead of 2); the valid one whose projected map
  // explains the most evidence wins, unless another explains nearly as much (ambiguous:
  // wait until the view tells them apart).
  // Hypotheses covered less than init_min_coverage (but kWeakCoverageRatio of it) are weak
  // detections: they may confirm a strong one, or be confirmed by one, never start alone.
  bool have = false, any_pose = false;
  const bool multi_polygon = geometry_.map.polygons.size() > 1;
  std::vector<Pose> rejected;  // poses of other map polygons whose sides were not covered enough
  std::vector<Pose> hypotheses;  // every map polygon's pose for this image polygon
  InitialPose init;
  Coverage best;
  double runner_up_px = 0;
  for (size_t pi = 0; pi < geometry_.map.polygons.size(); ++pi)
  {
    InitialPose candidate;
    const size_t corners = polygon.corners.size() + (polygon.open ? 2 : 0);
    if (geometry_.map.polygons[pi].corners_world.size() != corners ||
        !(polygon.open ? estimateInitialPoseOpen(polygon, geometry_.map, geometry_.k, params_.init, candidate,
                                                 static_cast<int>(pi))
                       : estimateInitialPose(polygon.corners, geometry_.map, geometry_.k, params_.init,
                                             candidate, static_cast<int>(pi))))
      continue;
    any_pose = true;
    // The corners' pose, or its planar-PnP twin when that explains clearly more of the
    // recent events (the primary fits the corners best; in a weak-perspective view the two
    // differ only in evidence beyond the corners, e.g. a second polygon's edges), or, when both
    // explain about as much, lies clearly closer to the events (the edges' slight convergence
    // tells the tilt: a far, nearly frontal square with a corner out of view started 20 deg
    // tilted the wrong way, its twin, the true pose, 1.5-2 % closer to the events).
    if (refine_events_ > 0)
      candidate.pose = refineWithWindowEvents(candidate.pose, recent);
    Coverage c = sideCoverage(candidate.pose, recent);
    double residual = -1;  // the candidate's point-to-line RMS, once needed
    for (Pose twin : candidate.alternatives)
    {
      if (refine_events_ > 0)
        twin = refineWithWindowEvents(twin, recent);
      const Coverage ct = sideCoverage(twin, recent);
      if (!valid(ct))
        continue;
      bool better = !valid(c) || ct.covered_px > kTwinMargin * c.covered_px;
      double twin_residual = -1;
      if (!better && ct.covered_px * kTwinMargin >= c.covered_px)
      {
        if (residual < 0)
          residual = refineResidualPx(candidate.pose, recent);
        twin_residual = refineResidualPx(twin, recent);
        better = twin_residual < kTwinResidualRatio * residual;
      }
      if (better)
      {
        candidate.pose = twin;
        c = ct;
        residual = twin_residual;
      }
    }
    if (multi_polygon)
      hypotheses.push_back(candidate.pose);
    if (!valid(c))
    {
      if (multi_polygon && c.min_fraction > 0)
        rejected.push_back(candidate.pose);
      continue;
    }
    if (geometry_.map.polygons.size() > 1 && !candidate.rotations.empty())
      pickRotationByEvidence(candidate, c, recent);
    if (!have || c.covered_px > best.covered_px)
    {
      if (have && !sameUpToSymmetry(init.pose, candidate.pose))
        runner_up_px = std::max(runner_up_px, best.covered_px);
      have = true;
      init = candidate;
      best = c;
    }
    else if (!sameUpToSymmetry(init.pose, candidate.pose))
      runner_up_px = std::max(runner_up_px, c.covered_px);
  }
  if (!have)
  {
    ++(any_pose ? stats_.coverage_failed : stats_.pose_failed);
    return Outcome::kNext;
  }
  if (std::isinf(init.up_margin))
    uprightAmongSymmetric(init);
  // A symmetric polygon fits its corners in several rotations (the square's four, 90 deg
  // apart): the map's up picks one, and near the +-45 deg roll where two are equally upright
  // (perspective tilting the projected up by a few degrees) the pick is a coin toss. Wait until
  // the view turns out of that band (a re-initialisation mid-roll took the square rotated by
  // 90 deg: 33 % / 88 deg off in a held-out sweep scene).
  if (runner_up_px > kAmbiguityRatio * best.covered_px || init.up_margin < params_.init_min_up_margin)
  {
    ++stats_.ambiguous;
    return Outcome::kNext;
  }
  // A square seen far off its normal projects to a thin parallelogram, which rows and diagonals
  // of any repeated pattern draw too (the screen loop's blinking dot grid started the tracker
  // 2.9 m off, 77-78 deg off the square's normal, explaining up to 0.44 of the window); the
  // sweep's correct starts were at most 63 deg off it.
  if (viewAngleDeg(init.pose, geometry_.map.polygons[init.polygon_index]) > params_.init_max_view_angle_deg)
  {
    ++stats_.too_oblique;
    return Outcome::kNext;
  }
  // An open polygon is matched from fewer sides, and with several map polygons a whole one can
  // be taken for another: the pose must also explain most of the recent events (a square's
  // three sides taken for the other square of a pair validated its visible sides and left the
  // real square's events unexplained: 0.28-0.34 of them explained in the sweep's false
  // initialisations, 0.6-1.0 in its correct ones; a whole square of a pair taken for the other,
  // which put the other beyond the image where no side needed covering, was the same).
  // Any pose must explain a share of them (init_min_explained): a polygon cut out of a pattern of
  // blobs (the screen loop's blinking alignment grid, whose dots lie along its sides but also all
  // around them) covered its sides and explained 0.12 of the window (2.5 m off); the sweep's
  // correct starts explained at least 0.45.
  const double explained = explainedFraction(init.pose, recent);
  if (explained < std::max(params_.init_min_explained, polygon.open || multi_polygon ? kOpenMinExplained : 0.0))
  {
    ++stats_.unexplained;
    return Outcome::kNext;
  }
  // With several map polygons, the hypothesis that puts more of the map in view must cover more
  // sides, some of which may hardly fire yet (a grey square's sides along the motion): one
  // rejected for that, which explains clearly more of the events than the winner (which put
  // the rest of the map out of view), makes the view ambiguous until its sides fill in (a
  // re-initialisation took the one square of a pair in full view for the other: 1.2 m off).
  for (const Pose& other : rejected)
    if (!sameUpToSymmetry(init.pose, other) && explainedFraction(other, recent) > explained + kRejectedExplainedMargin)
    {
      ++stats_.ambiguous;
      return Outcome::kNext;
    }
  // After a loss, with several map polygons: a winner far from the pose tracked before, while
  // another map polygon's hypothesis for the same image polygon lies near it, may have taken
  // one polygon for another; the rest of the map, which would tell them apart, may be hidden
  // (an occlusion) or not fire yet. Wait until the view decides or the prior expires (a pair's
  // square re-initialised as the other during an occlusion of the other: 1.2 m off, TRACKING).
  if (multi_polygon && have_prior_ && priorContradicts(init.pose, hypotheses))
  {
    ++stats_.ambiguous;
    return Outcome::kNext;
  }
  // The more of a polygon's outline is inferred rather than seen (sides stopping short of
  // their corners), the more it must repeat itself: one more agreeing detection when the
  // gaps exceed a quarter of the perimeter (a walking person's limbs made such a square).
  // An open polygon's missing side is inferred too.
  double roll_rate_deg_s = 0;
  if (!confirmed(init.pose, (polygon.open || polygon.gap_px > kInferredOutlineRatio * polygon.perimeter() ? 1 : 0) + extra_confirmations,
                 best.min_fraction >= params_.init_min_coverage, &roll_rate_deg_s))
  {
    ++stats_.unconfirmed;
    return Outcome::kStop;
  }
  // The map's up picks among a symmetric polygon's rotations (a finite up-margin) only while the
  // camera is near upright, which a camera rolling fast need not be: the confirming detections
  // measure the roll rate, and a fast roll waits until it slows down (mid-flip re-initialisations
  // at 920-1580 deg/s of roll took the square rotated by 90 deg; correct ones at most 230 deg/s).
  if (std::isfinite(init.up_margin) && roll_rate_deg_s > params_.init_max_roll_rate_deg_s)
  {
    ++stats_.ambiguous;
    return Outcome::kStop;
  }
  recent_.clear();
  if (!start(init.pose))
  {
    ++stats_.declined;
    hough_.reset();
    return Outcome::kNext;
  }
  ++stats_.accepted;
  last_polygon_ = polygon;
  return Outcome::kStarted;
}

bool TrackerInitializer::priorContradicts(const Pose& winner, const std::vector<Pose>& hypotheses) const
{
  const double off = positionError(winner, prior_);
  if (off <= kPriorFarRatio * prior_.p_world_camera().norm())
    return false;
  return std::any_of(hypotheses.begin(), hypotheses.end(), [&](const Pose& other) {
    return !sameUpToSymmetry(winner, other) && positionError(other, prior_) < kPriorCloserRatio * off;
  });
}

Pose TrackerInitializer::symmetric(const Eigen::Isometry3d& symmetry, const Pose& pose)
{
  // The camera at S * T_world_camera sees S(map) = map as the camera at T_world_camera sees it.
  return Pose::fromWorldCamera(Eigen::Matrix3d(symmetry.linear() * pose.R_world_camera()),
                               Eigen::Vector3d(symmetry * pose.p_world_camera()));
}

bool TrackerInitializer::sameUpToSymmetry(const Pose& a, const Pose& b) const
{
  return sameHypothesis(a, b) ||
         std::any_of(symmetries_.begin(), symmetries_.end(),
                     [&](const Eigen::Isometry3d& s) { return sameHypothesis(symmetric(s, a), b); });
}

void TrackerInitializer::uprightAmongSymmetric(InitialPose& init) const
{
  // The events chose this pose (or only one rotation of its polygon fits), but a symmetric map
  // looks the same from its symmetric poses (two squares side by side, turned by 180 deg): the
  // map's up picks among them, as it does among a symmetric polygon's rotations.
  if (symmetries_.empty())
    return;
  double best = upScore(init.pose, geometry_.k, map_points_, geometry_.map.up_world);
  double second = -std::numeric_limits<double>::infinity();
  Pose best_pose = init.pose;
  for (const auto& s : symmetries_)
  {
    const Pose pose = symmetric(s, init.pose);
    const double score = upScore(pose, geometry_.k, map_points_, geometry_.map.up_world);
    if (score > best)
    {
      second = best;
      best = score;
      best_pose = pose;
    }
    else
      second = std::max(second, score);
  }
  init.pose = best_pose;
  init.up_margin = best - second;
}

void TrackerInitializer::pickRotationByEvidence(InitialPose& candidate, Coverage& coverage,
                                                const RecentEvents& recent) const
{
  // The map's up picked the candidate among its polygon's rotations that fit the corners; the
  // rest of a map of several polygons lies elsewhere in each, so the events decide when one
  // rotation explains clearly more of them than every other (in a flip, the Hough window's
  // lagging roll made the up pick a triangle rotated by 120 deg: the square beside it was
  // placed out of view and its events left unexplained). Then the up no longer decides.
  Pose best_pose = candidate.pose;
  Coverage best = coverage;
  double runner_up_px = 0;
  for (Pose rotation : candidate.rotations)
  {
    if (refine_events_ > 0)
      rotation = refineWithWindowEvents(rotation, recent);
    const Coverage c = sideCoverage(rotation, recent);
    if (!valid(c))
      continue;
    if (c.covered_px > best.covered_px)
    {
      runner_up_px = best.covered_px;
      best_pose = rotation;
      best = c;
    }
    else
      runner_up_px = std::max(runner_up_px, c.covered_px);
  }
  if (best.covered_px <= kTwinMargin * runner_up_px)
    return;  // the events cannot tell them apart: the up decides
  candidate.pose = best_pose;
  candidate.up_margin = std::numeric_limits<double>::infinity();
  coverage = best;
}

bool TrackerInitializer::valid(const Coverage& coverage) const
{
  return coverage.min_fraction >= kWeakCoverageRatio * params_.init_min_coverage;
}

TrackerInitializer::RecentEvents TrackerInitializer::recentEvents() const
{
  RecentEvents r;
  r.window = hough_.windowPoints();
  r.evidence = hough_.evidencePoints();
  const size_t keep = std::min(r.window.size(), static_cast<size_t>(std::max(refine_events_, 0)));
  r.refine.assign(r.window.end() - static_cast<std::ptrdiff_t>(keep), r.window.end());
  return r;
}

Pose TrackerInitializer::refinePrior(const RecentEvents& recent) const
{
  // Coarse to fine: the camera moved while the track was lost, often further than the Hough's
  // attribution distance (BENCHMARKS.md, thirty-third session).
  // (At most 16 coarse stages, however small the Hough's distance.)
  const double fine = window_attribution_.max_orthogonal_px;
  Pose refined = prior_;
  double distance = params_.reacquire_capture_px;
  for (int stage = 0; stage < 16 && distance > fine * 1.01; ++stage, distance /= 2)
    refined = refineWithWindowEvents(refined, recent, distance);
  return refineWithWindowEvents(refined, recent, fine);
}

Pose TrackerInitializer::refineWithWindowEvents(const Pose& initial, const RecentEvents& recent) const
{
  return refineWithWindowEvents(initial, recent, window_attribution_.max_orthogonal_px);
}

Pose TrackerInitializer::refineWithWindowEvents(const Pose& initial, const RecentEvents& recent,
                                                double distance_px) const
{
  AttributionParams attribution = window_attribution_;
  attribution.max_orthogonal_px = distance_px;
  // The latest window events near the projected map segments pull the corner-based pose onto
  // all edge events (point-to-line Gauss-Newton, re-attributing every iteration).
  const std::vector<Eigen::Vector2d>& points = recent.refine;
  const LineMap& map = geometry_.map;
  const size_t n = map.segments.size();
  Pose pose = initial;
  std::vector<SegmentNormalEquations> eqs(n);
  // Each segment's attributed points enter its normal equations only through their weighted
  // moments (pose_estimator.h): no buffer of the points themselves.
  std::vector<PointMoments> moments(n);
  std::vector<int> counts(n);
  const double huber = params_.estimator.huber_px;
  for (int it = 0; it < 8; ++it)
  {
    std::fill(moments.begin(), moments.end(), PointMoments());
    std::fill(counts.begin(), counts.end(), 0);
    const std::vector<ProjectedSegment> proj = projectedMap(pose);
    for (const auto& p : points)
    {
      int segs[2];
      const int m = attributeEvent(p, proj.data(), static_cast<int>(n), attribution, segs);
      for (int j = 0; j < m; ++j)
      {
        moments[segs[j]].add(p, huberWeight(proj[segs[j]].normal.dot(p - proj[segs[j]].a), huber));
        ++counts[segs[j]];
      }
    }
    int used = 0;
    for (size_t i = 0; i < n; ++i)
    {
      eqs[i].active = counts[i] >= 5 && linearizeSegment(geometry_.k, pose, map.segments[i].p0_world,
                                                         map.segments[i].p1_world, moments[i], counts[i], eqs[i]);
      eqs[i].x_lin.setZero();
      used += eqs[i].active ? 1 : 0;
    }
    if (used < params_.min_visible_segments)
      return initial;
    Vector6d delta;
    if (!solveStep(eqs.data(), static_cast<int>(n), Vector6d::Zero(), 1e-6, delta))
      return initial;
    pose.applyCameraIncrement(delta);
    if (delta.norm() < 1e-9)
      break;
  }
  // Keep the refinement only if it stays close to the corner solution (a sanity bound).
  if (positionError(pose, initial) > 0.3 * initial.p_world_camera().norm() || !pose.t_camera_world.allFinite())
    return initial;
  return pose;
}

std::vector<ProjectedSegment> TrackerInitializer::projectedMap(const Pose& pose) const
{
  std::vector<ProjectedSegment> projected(geometry_.map.segments.size());
  geometry_.project(pose, false, projected);
  // (The initialiser validates and refines on whole segments in front only.)
  for (ProjectedSegment& s : projected)
    s.visible = s.in_front && !s.clipped();
  return projected;
}

namespace
{
/// Distance (px) from `p` to the nearest visible segment it lies beside (between the segment's
/// ends); infinite when it lies beside none.
double distanceBeside(const Eigen::Vector2d& p, const std::vector<ProjectedSegment>& segments)
{
  double d = std::numeric_limits<double>::infinity();
  for (const ProjectedSegment& s : segments)
    if (s.visible && s.parallelDistance(p) <= 0)
      d = std::min(d, s.orthogonalDistance(p));
  return d;
}
}  // namespace

double TrackerInitializer::refineResidualPx(const Pose& pose, const RecentEvents& recent) const
{
  const std::vector<ProjectedSegment> projected = projectedMap(pose);
  const double reach = window_attribution_.max_orthogonal_px;
  double sum_sq = 0;
  size_t n = 0;
  for (const auto& p : recent.refine)
  {
    const double d = distanceBeside(p, projected);
    if (d <= reach)
    {
      sum_sq += d * d;
      ++n;
    }
  }
  return n > 0 ? std::sqrt(sum_sq / static_cast<double>(n)) : std::numeric_limits<double>::infinity();
}

double TrackerInitializer::viewAngleDeg(const Pose& pose, const MapPolygon& polygon)
{
  const Eigen::Vector3d to_camera = (pose.p_world_camera() - cornerCentroid(polygon)).normalized();
  return std::acos(std::min(1.0, std::abs(frontNormal(polygon).normalized().dot(to_camera)))) * 180.0 / M_PI;
}

double TrackerInitializer::explainedFraction(const Pose& pose, const RecentEvents& recent) const
{
  if (recent.window.empty())
    return 0.0;
  const std::vector<ProjectedSegment> projected = projectedMap(pose);
  size_t explained = 0;
  for (const auto& p : recent.window)
    explained += distanceBeside(p, projected) <= window_attribution_.max_orthogonal_px ? 1 : 0;
  return static_cast<double>(explained) / static_cast<double>(recent.window.size());
}

TrackerInitializer::Coverage TrackerInitializer::sideCoverage(const Pose& pose, const RecentEvents& recent) const
{
  Coverage result;
  const LineMap& map = geometry_.map;
  const PinholeK& k = geometry_.k;
  const int width = geometry_.width, height = geometry_.height;
  // Every visible side must be backed by events along most of its visible length; corners may
  // be outside the image (a partial view) as long as enough sides are in view.
  constexpr double kCell = 3.0;
  const double d_max = window_attribution_.max_orthogonal_px;
  const double shift = kSurroundingShift * d_max;
  double worst = 1.0;
  int visible = 0;
  // Per cell along the side: bit 0 the side itself, bit 1 / bit 2 the strips `shift` to its
  // left / right.
  std::vector<unsigned char> filled;
  double surrounding_cells = 0, total_cells = 0;
  for (const auto& seg : map.segments)
  {
    const Eigen::Vector3d a = pose.toCamera(seg.p0_world), b = pose.toCamera(seg.p1_world);
    if (a.z() <= params_.min_depth_m || b.z() <= params_.min_depth_m)
      return result;
    Eigen::Vector2d ca, cb;
    const double len =
        clippedLength(k.project(a), k.project(b), -0.5, -0.5, width - 0.5, height - 0.5, &ca, &cb);
    if (len < params_.min_visible_length_px)
      continue;
    ++visible;
    ProjectedSegment ps;
    ps.set(ca, cb);
    const int cells = std::max(1, static_cast<int>(len / kCell));
    filled.assign(cells, 0);
    // Only points within shift + d_max of the side can count (the cells near it; a cell's bits
    // are or-ed, so the order of the points does not matter).
    recent.evidenceGrid().forEachNearSegment(ca, cb, shift + d_max, [&](const Eigen::Vector2d& p) {
      const double t = ps.dir.dot(p - ps.a);
      if (t < 0 || t >= len)
        return;
      const double d = ps.normal.dot(p - ps.a);
      const unsigned char bit = std::abs(d) <= d_max           ? 1
                                : std::abs(d - shift) <= d_max ? 2
                                : std::abs(d + shift) <= d_max ? 4
                                                               : 0;
      if (bit)
        filled[std::min(cells - 1, static_cast<int>(t / len * cells))] |= bit;
    });
    int n = 0, left = 0, right = 0;
    for (unsigned char f : filled)
    {
      n += f & 1;
      left += (f >> 1) & 1;
      right += (f >> 2) & 1;
    }
    worst = std::min(worst, static_cast<double>(n) / cells);
    result.covered_px += static_cast<double>(n) / cells * len;
    surrounding_cells += std::min(left, right);
    total_cells += cells;
  }
  if (visible < params_.min_visible_segments)
    return result;
  // An edge is a line of events with a quieter side (the side it moves towards, or both when it
  // is slow); a polygon drawn inside a blob of events (heavy background activity on a fast
  // flip's smear) is covered wherever it is drawn, and so are the strips beside its sides. On the
  // 192-scene sweep the correct starts' quieter strips held at most 0.27 of their cells, the
  // false polygons drawn in such a blob 0.65-0.83.
  if (total_cells > 0 && surrounding_cells / total_cells > params_.init_max_surrounding_coverage)
    return result;
  // A polygon's inside is quiet; a "polygon" cut out of a band of smeared events is not.
  for (const auto& poly : map.polygons)
  {
    std::vector<ProjectedSegment> sides;
    for (size_t i = 0; i < poly.corners_world.size(); ++i)
    {
      ProjectedSegment ps;
      ps.set(k.project(pose.toCamera(poly.corners_world[i])),
             k.project(pose.toCamera(poly.corners_world[(i + 1) % poly.corners_world.size()])));
      sides.push_back(ps);
    }
    int on_sides = 0, inside = 0;
    // A point on a side or inside the polygon lies in its corners' box grown by the attribution
    // distance; the others count for neither.
    Eigen::Vector2d lo = sides.front().a, hi = lo;
    for (const auto& sd : sides)
    {
      lo = lo.cwiseMin(sd.a).cwiseMin(sd.b);
      hi = hi.cwiseMax(sd.a).cwiseMax(sd.b);
    }
    const Eigen::Vector2d grow = Eigen::Vector2d::Constant(window_attribution_.max_orthogonal_px);
    recent.windowGrid().forEachInBox(lo - grow, hi + grow, [&](const Eigen::Vector2d& p) {
      double nearest = 1e300;
      int sign_pos = 0, sign_neg = 0;
      for (const auto& sd : sides)
      {
        const double d = sd.normal.dot(p - sd.a);
        (d >= 0 ? sign_pos : sign_neg)++;
        if (sd.parallelDistance(p) < 0)
          nearest = std::min(nearest, std::abs(d));
      }
      if (nearest <= window_attribution_.max_orthogonal_px)
        ++on_sides;
      else if ((sign_pos == 0 || sign_neg == 0) && nearest > 2 * window_attribution_.max_orthogonal_px)
        ++inside;
    });
    if (inside > params_.init_max_inside_ratio * std::max(on_sides, 1))
      return result;
  }
  result.min_fraction = worst;
  return result;
}
}  // namespace dvs_line_tracker
