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
  Eigen::Vector2d a = Eigen::Vector2d::Zero();  ///< projection of the map segment's p0
  Eigen::Vector2d b = Eigen::Vector2d::Zero();  ///< projection of p1
  Eigen::Vector2d dir = Eigen::Vector2d::UnitX();  ///< unit vector a -> b
  Eigen::Vector2d normal = Eigen::Vector2d::UnitY();  ///< dir rotated by +90 deg
  double length = 0;
  bool in_front = false;  ///< both endpoints in front of the camera
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
class SegmentBuffer
{
public:
  explicit SegmentBuffer(int capacity = 8)
    : points_(capacity), offsets_(capacity, 0.0), weights_(capacity, 0.0), stamps_(capacity, 0)
  {
  }

  int capacity() const { return static_cast<int>(points_.size()); }
  int size() const { return size_; }
  const Eigen::Vector2d& point(int i) const { return points_[i]; }
  double weight(int i) const { return weights_[i]; }
  /// Insertion count of the buffer when point `i` was inserted (its age in insertions: clock() - stamp(i)).
  uint64_t stamp(int i) const { return stamps_[i]; }
  uint64_t clock() const { return clock_; }
  /// Weighted moments of the stored points.
  const PointMoments& moments() const { return moments_; }
  void clear()
  {
    size_ = 0;
    moments_ = PointMoments();
  }

  /// Insert `p` given the segment's current projection. Returns the slot written.
  int insert(const Eigen::Vector2d& p, const ProjectedSegment& seg, double max_orthogonal_px = 1e300,
             double max_parallel_px = 1e300, double max_motion_px = 1e300, double huber_px = 1e300)
  {
    ++clock_;
    const double offset_new = seg.normal.dot(p - seg.a);
    const double weight_new = std::abs(offset_new) <= huber_px ? 1.0 : huber_px / std::abs(offset_new);
    // One pass over the stored events: drop those the line has moved away from (expire()), and
    // among the others find the replacement candidates of a full buffer. A dropped event is
    // replaced by the last one, which is examined next: the candidates are found in the order
    // of the compacted buffer, as by an expire() followed by a search. (A buffer that is not
    // full needs no candidates: then only the expiry, if any.)
    const bool expiring = max_motion_px < 1e299;
    const bool full = size_ == capacity();
    if (!full && !expiring)
      return append(p, offset_new, weight_new);
    const double s_new = seg.dir.dot(p - seg.a);
    int closest = 0, oldest = -1, stale = -1;
    double best = 1e300, worst_excess = 0;
    for (int i = 0; i < size_;)
    {
      const Eigen::Vector2d v = points_[i] - seg.a;
      const double offset = seg.normal.dot(v);
      if (expiring && std::abs(offset - offsets_[i]) > max_motion_px)
      {
        removeAt(i);
        continue;
      }
      if (!full)
      {
        ++i;
        continue;
      }
      const double s = seg.dir.dot(v);
      const double excess =
          std::max(std::abs(offset) - max_orthogonal_px, std::max(-s, s - seg.length) - max_parallel_px);
      if (excess > worst_excess)
      {
        worst_excess = excess;
        stale = i;
      }
      const double ds = std::abs(s - s_new);
      if (ds < best)
      {
        best = ds;
        closest = i;
      }
      if (oldest < 0 || stamps_[i] < stamps_[oldest])
        oldest = i;
      ++i;
    }
    if (size_ < capacity())
      return append(p, offset_new, weight_new);
    const double threshold = 0.5 * seg.length / capacity();
    const int slot = stale >= 0 ? stale : (best < threshold ? closest : oldest);
    moments_.add(points_[slot], weights_[slot], -1.0);
    return store(slot, p, offset_new, weight_new);
  }

  /// Drop the stored events over which the projected line `seg` has moved farther than
  /// `max_motion_px` (along its normal, at the event) since they were inserted.
  void expire(const ProjectedSegment& seg, double max_motion_px)
  {
    for (int i = 0; i < size_;)
    {
      const double offset = seg.normal.dot(points_[i] - seg.a);
      if (std::abs(offset - offsets_[i]) > max_motion_px)
        removeAt(i);
      else
        ++i;
    }
  }

private:
  int append(const Eigen::Vector2d& p, double offset, double weight) { return store(size_++, p, offset, weight); }
  int store(int slot, const Eigen::Vector2d& p, double offset, double weight)
  {
    points_[slot] = p;
    offsets_[slot] = offset;
    weights_[slot] = weight;
    stamps_[slot] = clock_;
    moments_.add(p, weight);
    if (++changes_since_refresh_ >= 4096)
      refreshMoments();
    return slot;
  }

  /// Remove stored event `i` (the last one takes its slot).
  void removeAt(int i)
  {
    moments_.add(points_[i], weights_[i], -1.0);
    ++changes_since_refresh_;
    --size_;
    points_[i] = points_[size_];
    offsets_[i] = offsets_[size_];
    weights_[i] = weights_[size_];
    stamps_[i] = stamps_[size_];
  }

  /// Recompute the moments from the points (bounds the rounding drift of the running sums).
  void refreshMoments()
  {
    moments_ = PointMoments();
    for (int i = 0; i < size_; ++i)
      moments_.add(points_[i], weights_[i]);
    changes_since_refresh_ = 0;
  }

  std::vector<Eigen::Vector2d> points_;
  std::vector<double> offsets_;  ///< signed distance to the projected line when inserted
  std::vector<double> weights_;  ///< Huber weight fixed at insertion
  std::vector<uint64_t> stamps_;
  PointMoments moments_;
  int size_ = 0;
  int changes_since_refresh_ = 0;
  uint64_t clock_ = 0;
};
}  // namespace dvs_line_tracker
