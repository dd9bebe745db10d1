#pragma once
// Per-event segment attribution (thesis 4.2.2, Eq. 4.2-4.4 and Fig. 4.5) and the per-segment
// event buffers with replacement of the closest old event (Fig. 4.6). Header-only: these run
// for every event and must inline; nothing here allocates after construction.
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace dvs_line_tracker
{
/// A map segment projected into the ideal (undistorted) image.
struct ProjectedSegment
{
  Eigen::Vector3d pc0 = Eigen::Vector3d::Zero();  ///< the map segment's p0 in the camera frame (or where it was clipped)
  Eigen::Vector3d pc1 = Eigen::Vector3d::Zero();  ///< and its p1
  Eigen::Vector2d a = Eigen::Vector2d::Zero();  ///< projection of the map segment's p0 (when in front)
  Eigen::Vector2d b = Eigen::Vector2d::Zero();  ///< projection of p1
  Eigen::Vector2d dir = Eigen::Vector2d::UnitX();  ///< unit vector a -> b
  Eigen::Vector2d normal = Eigen::Vector2d::UnitY();  ///< dir rotated by +90 deg
  double length = 0;
  bool in_front = false;  ///< some of it in front of the camera (a..b: that part)
  /// Where the part in front begins and ends along the map segment (0 and 1: all of it; else
  /// it was clipped at the near plane, an endpoint being behind the camera).
  double t0 = 0, t1 = 1;
  bool clipped() const { return t0 != 0 || t1 != 1; }
  bool visible = false;   ///< in front and at least the minimum length inside the image
  double visible_length = 0;  ///< length inside the image (where the owner computes visibility)

  void set(const Eigen::Vector2d& pa, const Eigen::Vector2d& pb)
  {
    a = pa;
    b = pb;
    const Eigen::Vector2d e = b - a;
    length = e.norm();
    dir = length > 1e-12 ? Eigen::Vector2d(e / length) : Eigen::Vector2d(1, 0);
    normal = Eigen::Vector2d(-dir.y(), dir.x());
  }
  /// Orthogonal distance (Eq. 4.2), >= 0.
  double orthogonalDistance(const Eigen::Vector2d& p) const { return std::abs(normal.dot(p - a)); }
  /// Signed parallel distance to the closer endpoint (Eq. 4.3): negative between the endpoints.
  double parallelDistance(const Eigen::Vector2d& p) const
  {
    const double t = dir.dot(p - a);
    return std::max(-t, t - length);
  }
};

/// Length (px) of the part of a segment inside [x0,x1] x [y0,y1] (Liang-Barsky clipping);
/// `clipped_a`, `clipped_b` receive the inside part when it is not empty.
double clippedLength(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double x0, double y0, double x1, double y1,
                     Eigen::Vector2d* clipped_a = nullptr, Eigen::Vector2d* clipped_b = nullptr);

struct AttributionParams
{
  double max_orthogonal_px = 2.0;  ///< d_max (thesis: 2 px)
  double max_parallel_px = 10.0;   ///< d_par_max (thesis: 10 px)
};

/// Which of the thesis's regions (Fig. 4.5) an event falls in with respect to the segments.
enum class AttributionRegion : uint8_t
{
  kNone,        ///< in range of no segment, or of more than two: discarded
  kSingle,      ///< in range of exactly one segment
  kOnlyFirst,   ///< region A/B: between the endpoints of one, outside the other's: that one only
  kBoth,        ///< region C: outside the endpoints of both: both
  kInsideBoth,  ///< region D: between the endpoints of both: discarded (keeps polygons from shrinking)
};

/// Attribute an event at `p` (ideal pixels). Writes up to two segment indices into `out`,
/// returns how many. Only visible segments take part.
inline int attributeEvent(const Eigen::Vector2d& p, const ProjectedSegment* segs, int num_segs,
                          const AttributionParams& params, int out[2], AttributionRegion* region = nullptr)
{
  int in_range[3];
  double par[3];
  int count = 0;
  for (int i = 0; i < num_segs; ++i)
  {
    const ProjectedSegment& s = segs[i];
    if (!s.visible)
      continue;
    const Eigen::Vector2d v = p - s.a;
    const double d_orth = std::abs(s.normal.dot(v));
    if (d_orth > params.max_orthogonal_px)
      continue;
    const double t = s.dir.dot(v);
    const double d_par = std::max(-t, t - s.length);
    if (d_par > params.max_parallel_px)
      continue;
    if (count == 2)
    {
      count = 3;
      break;
    }
    in_range[count] = i;
    par[count] = d_par;
    ++count;
  }
  AttributionRegion r = AttributionRegion::kNone;
  int n = 0;
  if (count == 1)
  {
    out[n++] = in_range[0];
    r = AttributionRegion::kSingle;
  }
  else if (count == 2)
  {
    const bool inside0 = par[0] < 0, inside1 = par[1] < 0;
    if (inside0 && inside1)
      r = AttributionRegion::kInsideBoth;
    else if (!inside0 && !inside1)
    {
      out[n++] = in_range[0];
      out[n++] = in_range[1];
      r = AttributionRegion::kBoth;
    }
    else
    {
      out[n++] = inside0 ? in_range[0] : in_range[1];
      r = AttributionRegion::kOnlyFirst;
    }
  }
  if (region)
    *region = r;
  return n;
}

/// The Huber weight of a point `offset` px from its line (1 within `huber_px`, huber_px / |offset| beyond).
inline double huberWeight(double offset, double huber_px)
{
  const double d = std::abs(offset);
  return d <= huber_px ? 1.0 : huber_px / d;
}

/// Weighted raw moments of a buffer's points, kept up to date on every change so that a
/// segment's normal equations cost O(1) whatever the buffer size (pose_estimator.cpp).
struct PointMoments
{
  double w = 0, x = 0, y = 0, xx = 0, xy = 0, yy = 0;

  void add(const Eigen::Vector2d& p, double weight, double sign = 1.0)
  {
    const double sw = sign * weight;
    w += sw;
    x += sw * p.x();
    y += sw * p.y();
    xx += sw * p.x() * p.x();
    xy += sw * p.x() * p.y();
    yy += sw * p.y() * p.y();
  }
};

/// The events attributed to one segment: a fixed number of slots, each event with a Huber
/// weight fixed at its insertion (from its distance to the projected line then).
/// Before a new event is stored, events over which the projected line has moved farther than
/// `max_motion_px` since their insertion are dropped (the buffer then spans a bounded image
/// motion). When the buffer is full, the new event replaces, in this order: a stored event that
/// no longer lies in the segment's attribution range (farther than `max_orthogonal_px` from the
/// current projected line or `max_parallel_px` beyond its ends: stale, e.g. left behind by a
/// moving corner); else the stored event closest to it along the segment when that one is
/// closer than half the spacing of uniformly spread events (thesis Fig. 4.6b); else the oldest.
///
/// Most insertions drop nothing: the buffer keeps a bounding box of its events in the frame of
/// the line it last examined them against (the reference line), and while the current line is
/// close enough to that one that no event of the box can have become stale or moved too far,
/// only the replacement search runs (one pass). Otherwise every event is examined (as the
/// rule above says) and the reference is moved to the current line. The slots are stored as
/// separate arrays (x, y, offset, weight, stamp) so that the passes vectorise.
class SegmentBuffer
{
public:
  explicit SegmentBuffer(int capacity = 8)
    : x_(capacity, 0.0)
    , y_(capacity, 0.0)
    , offsets_(capacity, 0.0)
    , weights_(capacity, 0.0)
    , stamps_(capacity, 0)
    , older_(capacity, -1)
    , newer_(capacity, -1)
    , offset_now_(capacity, 0.0)
    , along_now_(capacity, 0.0)
    , along_distance_(capacity, 0.0)
  {
  }

  int capacity() const { return static_cast<int>(x_.size()); }
  int size() const { return size_; }
  Eigen::Vector2d point(int i) const { return Eigen::Vector2d(x_[i], y_[i]); }
  double weight(int i) const { return weights_[i]; }
  /// Signed distance of point `i` from its segment's projected line when it was inserted.
  double offset(int i) const { return offsets_[i]; }
  /// Insertion count of the buffer when point `i` was inserted (its age in insertions: clock() - stamp(i)).
  uint64_t stamp(int i) const { return stamps_[i]; }
  uint64_t clock() const { return clock_; }
  /// Weighted moments of the stored points.
  const PointMoments& moments() const { return moments_; }
  /// Insertions that examined every stored event (the others ran only the replacement search).
  uint64_t examinations() const { return examinations_; }
  void clear()
  {
    size_ = 0;
    oldest_ = newest_ = -1;
    moments_ = PointMoments();
    has_reference_ = false;
  }

  /// Insert `p` given the segment's current projection. Returns the slot written.
  int insert(const Eigen::Vector2d& p, const ProjectedSegment& seg, double max_orthogonal_px = 1e300,
             double max_parallel_px = 1e300, double max_motion_px = 1e300, double huber_px = 1e300)
  {
    ++clock_;
    const double offset_new = seg.normal.dot(p - seg.a);
    const double weight_new = huberWeight(offset_new, huber_px);
    // Drop the events the line has moved away from (as expire() does: a dropped event is
    // replaced by the last one), then, in a full buffer, find the replacement among the others.
    // (A buffer that is not full needs no candidates: then only the expiry, if any.)
    const bool expiring = max_motion_px < 1e299;
    if (size_ < capacity() && !expiring)
      return append(p, offset_new, weight_new);
    if (size_ == capacity() && has_reference_ && nothingToDrop(seg, max_orthogonal_px, max_parallel_px, max_motion_px))
    {
      const int slot = closestOrOldest(seg, seg.dir.dot(p - seg.a));
      moments_.add(point(slot), weights_[slot], -1.0);
      unlinkAge(slot);
      return store(slot, p, offset_new, weight_new);
    }
    ++examinations_;
    placeOnLine(seg);
    if (expiring)
      dropMoved(max_motion_px);
    int slot;
    if (size_ < capacity())
      slot = append(p, offset_new, weight_new);
    else
    {
      slot = replacementSlot(seg, seg.dir.dot(p - seg.a), max_orthogonal_px, max_parallel_px);
      moments_.add(point(slot), weights_[slot], -1.0);
      unlinkAge(slot);
      store(slot, p, offset_new, weight_new);
    }
    setReference(seg);
    return slot;
  }

  /// Drop the stored events over which the projected line `seg` has moved farther than
  /// `max_motion_px` (along its normal, at the event) since they were inserted.
  void expire(const ProjectedSegment& seg, double max_motion_px)
  {
    if (has_reference_)
    {
      double c[3];
      offsetCoefficients(seg, c);
      if (motionBounded(c, max_motion_px))
        return;
    }
    placeOnLine(seg);
    dropMoved(max_motion_px);
    setReference(seg);
  }

private:
  /// Every stored event's signed offset from `seg`'s line and position along it from `a`
  /// (offset_now_, along_now_).
  void placeOnLine(const ProjectedSegment& seg)
  {
    const double ax = seg.a.x(), ay = seg.a.y();
    const double nx = seg.normal.x(), ny = seg.normal.y(), dx = seg.dir.x(), dy = seg.dir.y();
    const double* const xs = x_.data();
    const double* const ys = y_.data();
    double* const offset = offset_now_.data();
    double* const along = along_now_.data();
    const int n = size_;
    for (int i = 0; i < n; ++i)
    {
      const double vx = xs[i] - ax, vy = ys[i] - ay;
      offset[i] = nx * vx + ny * vy;
      along[i] = dx * vx + dy * vy;
    }
  }

  /// Drop the stored events whose offset from the line (placeOnLine()) differs from their
  /// offset at insertion by more than `max_motion_px`; the last event takes a dropped one's
  /// slot (and is examined next).
  void dropMoved(double max_motion_px)
  {
    int moved = 0;
    for (int i = 0; i < size_; ++i)
      moved += std::abs(offset_now_[i] - offsets_[i]) > max_motion_px;
    for (int i = 0; moved > 0 && i < size_;)
    {
      if (std::abs(offset_now_[i] - offsets_[i]) > max_motion_px)
      {
        removeAt(i);
        offset_now_[i] = offset_now_[size_];
        along_now_[i] = along_now_[size_];
        --moved;
      }
      else
        ++i;
    }
  }

  /// The slot a new event at `along_new` (along the line) takes in a full buffer, from
  /// placeOnLine()'s results: the first stale event, else the closest if within half the
  /// spacing, else the oldest.
  int replacementSlot(const ProjectedSegment& seg, double along_new, double max_orthogonal_px,
                      double max_parallel_px)
  {
    const double length = seg.length;
    const double* const offset = offset_now_.data();
    const double* const along = along_now_.data();
    const int n = size_;
    int stale = -1;
    double worst_excess = 0;
    for (int i = 0; i < n; ++i)
    {
      const double excess = std::max(std::abs(offset[i]) - max_orthogonal_px,
                                     std::max(-along[i], along[i] - length) - max_parallel_px);
      if (excess > worst_excess)
      {
        worst_excess = excess;
        stale = i;
      }
    }
    return stale >= 0 ? stale : closestOrOldest(seg, along_new);
  }

  /// The stored event closest to `along_new` along `seg` if closer than half the spacing of
  /// uniformly spread events, else the oldest. Written as three passes (distances, their
  /// minimum, the first slot holding it) so that the first two vectorise: a single argmin pass
  /// is one long dependency chain (it was a quarter of the tracking time).
  int closestOrOldest(const ProjectedSegment& seg, double along_new)
  {
    const double ax = seg.a.x(), ay = seg.a.y(), dx = seg.dir.x(), dy = seg.dir.y();
    const double* const xs = x_.data();
    const double* const ys = y_.data();
    double* const distance = along_distance_.data();
    const int n = size_;
    if (n == 0)
      return oldest_;
    // (Not dx * x + dy * y - c with the constants folded: its rounding differs, and pixel-grid
    // events are often exactly as far on either side of a new one, where the rounding picks.)
    for (int i = 0; i < n; ++i)
      distance[i] = std::abs(dx * (xs[i] - ax) + dy * (ys[i] - ay) - along_new);
    const double best = Eigen::Map<const Eigen::ArrayXd>(distance, n).minCoeff();
    if (!(best < 0.5 * seg.length / capacity()))
      return oldest_;  // the least stamp (the age list is in insertion order)
    int closest = 0;
    while (distance[closest] != best)
      ++closest;
    return closest;
  }

  /// True when, by the reference box, no stored event can be stale against `seg` (beyond
  /// `max_orthogonal_px` / `max_parallel_px`) or have moved farther than `max_motion_px` since
  /// its insertion. (False means: examine every event.) A margin of kBoundMarginPx covers the
  /// rounding of the bound against the per-event test it stands for.
  bool nothingToDrop(const ProjectedSegment& seg, double max_orthogonal_px, double max_parallel_px,
                     double max_motion_px) const
  {
    // A point s ref_dir + o ref_normal from the reference's a lies c0 + c1 s + c2 o from the
    // current line and e0 + e1 s + e2 o along it from its a: linear, so extreme at the corners.
    double c[3];
    offsetCoefficients(seg, c);
    const Eigen::Vector2d da = ref_a_ - seg.a;
    const double e0 = seg.dir.dot(da), e1 = seg.dir.dot(ref_dir_), e2 = seg.dir.dot(ref_normal_);
    double lo, hi;
    rangeOverBox(c[0], c[1], c[2], &lo, &hi);
    if (std::max(-lo, hi) > max_orthogonal_px - kBoundMarginPx)
      return false;
    rangeOverBox(e0, e1, e2, &lo, &hi);
    if (-lo > max_parallel_px - kBoundMarginPx || hi - seg.length > max_parallel_px - kBoundMarginPx)
      return false;
    return max_motion_px >= 1e299 || motionBounded(c, max_motion_px);
  }

  /// The offset of a reference-frame point (s, o) from `seg`'s line is c[0] + c[1] s + c[2] o.
  void offsetCoefficients(const ProjectedSegment& seg, double c[3]) const
  {
    c[0] = seg.normal.dot(ref_a_ - seg.a);
    c[1] = seg.normal.dot(ref_dir_);
    c[2] = seg.normal.dot(ref_normal_);
  }

  /// True when, by the reference box, no stored event can have moved farther than
  /// `max_motion_px` since its insertion from the line whose offsetCoefficients() are `c`.
  bool motionBounded(const double c[3], double max_motion_px) const
  {
    // Motion since insertion = (offset now - offset from the reference) + (offset from the
    // reference - offset at insertion); the second term is at most motion_at_reference_.
    double lo, hi;
    rangeOverBox(c[0], c[1], c[2] - 1.0, &lo, &hi);
    return std::max(-lo, hi) + motion_at_reference_ <= max_motion_px - kBoundMarginPx;
  }

  /// The range of k0 + k1 s + k2 o over the reference box.
  void rangeOverBox(double k0, double k1, double k2, double* lo, double* hi) const
  {
    const double s0 = k1 * s_lo_, s1 = k1 * s_hi_, o0 = k2 * o_lo_, o1 = k2 * o_hi_;
    *lo = k0 + std::min(s0, s1) + std::min(o0, o1);
    *hi = k0 + std::max(s0, s1) + std::max(o0, o1);
  }

  /// Make `seg`'s line the reference and bound the stored events in its frame.
  void setReference(const ProjectedSegment& seg)
  {
    ref_a_ = seg.a;
    ref_dir_ = seg.dir;
    ref_normal_ = seg.normal;
    has_reference_ = true;
    s_lo_ = o_lo_ = std::numeric_limits<double>::infinity();
    s_hi_ = o_hi_ = -std::numeric_limits<double>::infinity();
    motion_at_reference_ = 0;
    for (int i = 0; i < size_; ++i)
      addToBox(i);
  }

  /// Grow the reference box (and the motion bound) by stored event `i`. Events removed later
  /// stay inside the box: it only ever over-covers, until the next setReference().
  void addToBox(int i)
  {
    const double vx = x_[i] - ref_a_.x(), vy = y_[i] - ref_a_.y();
    const double s = ref_dir_.x() * vx + ref_dir_.y() * vy;
    const double o = ref_normal_.x() * vx + ref_normal_.y() * vy;
    s_lo_ = std::min(s_lo_, s);
    s_hi_ = std::max(s_hi_, s);
    o_lo_ = std::min(o_lo_, o);
    o_hi_ = std::max(o_hi_, o);
    motion_at_reference_ = std::max(motion_at_reference_, std::abs(o - offsets_[i]));
  }

  int append(const Eigen::Vector2d& p, double offset, double weight) { return store(size_++, p, offset, weight); }
  /// Write the event into `slot` (appended, or unlinked from the age list before) and make it
  /// the newest.
  int store(int slot, const Eigen::Vector2d& p, double offset, double weight)
  {
    older_[slot] = newest_;
    newer_[slot] = -1;
    if (newest_ >= 0)
      newer_[newest_] = slot;
    else
      oldest_ = slot;
    newest_ = slot;
    x_[slot] = p.x();
    y_[slot] = p.y();
    offsets_[slot] = offset;
    weights_[slot] = weight;
    stamps_[slot] = clock_;
    if (has_reference_)
      addToBox(slot);
    moments_.add(p, weight);
    if (++changes_since_refresh_ >= 4096)
      refreshMoments();
    return slot;
  }

  /// Remove stored event `i` (the last one takes its slot, and its place in the age list).
  void removeAt(int i)
  {
    moments_.add(point(i), weights_[i], -1.0);
    ++changes_since_refresh_;
    unlinkAge(i);
    --size_;
    if (i == size_)
      return;
    x_[i] = x_[size_];
    y_[i] = y_[size_];
    offsets_[i] = offsets_[size_];
    weights_[i] = weights_[size_];
    stamps_[i] = stamps_[size_];
    older_[i] = older_[size_];
    newer_[i] = newer_[size_];
    (older_[i] >= 0 ? newer_[older_[i]] : oldest_) = i;
    (newer_[i] >= 0 ? older_[newer_[i]] : newest_) = i;
  }

  /// Take slot `i` out of the age list (its neighbours close up).
  void unlinkAge(int i)
  {
    (older_[i] >= 0 ? newer_[older_[i]] : oldest_) = newer_[i];
    (newer_[i] >= 0 ? older_[newer_[i]] : newest_) = older_[i];
  }

  /// Recompute the moments from the points (bounds the rounding drift of the running sums).
  void refreshMoments()
  {
    moments_ = PointMoments();
    for (int i = 0; i < size_; ++i)
      moments_.add(point(i), weights_[i]);
    changes_since_refresh_ = 0;
  }

  std::vector<double> x_, y_;    ///< the stored events (ideal pixels)
  std::vector<double> offsets_;  ///< signed distance to the projected line when inserted
  std::vector<double> weights_;  ///< Huber weight fixed at insertion
  std::vector<uint64_t> stamps_;
  // The stored events in insertion order (a doubly linked list over the slots, oldest first), so
  // that the oldest is known without a pass over the stamps.
  std::vector<int> older_, newer_;
  int oldest_ = -1, newest_ = -1;
  std::vector<double> offset_now_, along_now_;  ///< per insert: each event's offset from / position along the line now
  std::vector<double> along_distance_;  ///< per insert: each event's distance along the line from the new one
  // The reference line and the box [s_lo_, s_hi_] x [o_lo_, o_hi_] holding every stored event
  // in its frame (along ref_dir_ and ref_normal_ from ref_a_); the largest motion of an event
  // between its insertion and the reference.
  static constexpr double kBoundMarginPx = 1e-7;
  bool has_reference_ = false;
  Eigen::Vector2d ref_a_ = Eigen::Vector2d::Zero(), ref_dir_ = Eigen::Vector2d::UnitX(),
                  ref_normal_ = Eigen::Vector2d::UnitY();
  double s_lo_ = 0, s_hi_ = 0, o_lo_ = 0, o_hi_ = 0, motion_at_reference_ = 0;
  PointMoments moments_;
  int size_ = 0;
  int changes_since_refresh_ = 0;
  uint64_t clock_ = 0;
  uint64_t examinations_ = 0;
};
}  // namespace dvs_line_tracker
