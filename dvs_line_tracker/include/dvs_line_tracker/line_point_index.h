#pragma once
// The points of one Hough detection window indexed by their Hough radius along each of the
// accumulator's angles (a counting sort per angle, built the first time a query needs that
// angle): the points near a line, or whose Hough curve passes through a bin, are looked for in a
// few radius buckets instead of the whole window. Queries return a superset, in the points'
// own order, which the caller tests exactly; so a detection finds the same segments as a scan of
// the whole window would, bit for bit.
#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace dvs_line_tracker
{
class LinePointIndex
{
public:
  /// `num_angles` angles k * pi / num_angles; radius buckets of `bucket_px` over
  /// [-r_max, r_max] measured from `centre` (points beyond go to the end buckets).
  LinePointIndex(int num_angles, double r_max, double bucket_px, const Eigen::Vector2d& centre);

  /// Buckets the caller computed already (a Hough detector's curve bins, hough_line_detector.h):
  /// point i's bucket at angle k is bins[((start + i) % capacity) * stride + k], -1 where the
  /// caller's grid ended (the index then computes it). They must be this index's buckets:
  /// floor((r + r_max) / bucket_px) of the point's radius r at angle k.
  struct KnownBuckets
  {
    const int32_t* bins = nullptr;
    int stride = 0, start = 0, capacity = 0;
  };

  /// Index a new set of points (kept by reference: it must outlive the queries until the next
  /// reset). Nothing is sorted until a query needs it; the memory is reused. With `known`, the
  /// sorting reads the points' buckets from there instead of computing them (kept by reference
  /// as well).
  void reset(const std::vector<Eigen::Vector2d>& points, const KnownBuckets& known);
  void reset(const std::vector<Eigen::Vector2d>& points) { reset(points, {nullptr, 0, 0, 0}); }

  /// Replaces `out` with the indices, ascending, of every point p whose radius from the
  /// centre, (p - centre) . (cos phi, sin phi), may lie in [r_lo, r_hi] for some angle phi
  /// within `half_width` of `theta` (any real angle; a superset of those points).
  void candidates(double theta, double r_lo, double r_hi, double half_width, std::vector<int>& out);

  /// Replaces `out` with the indices, ascending, of a superset of the points within
  /// `distance` of `line_r` = p . (cos theta, sin theta) (the line in the points' own
  /// coordinates, as ImageLine).
  void nearLine(double theta, double line_r, double distance, std::vector<int>& out);

  /// How many angles have been sorted since the last reset (for tests).
  int anglesBuilt() const;

private:
  void build(int k);
  /// Point i's bucket at angle k, computed.
  int bucketAt(int k, const Eigen::Vector2d& p) const;

  int num_angles_, num_buckets_;
  double r_max_, bucket_px_;
  Eigen::Vector2d centre_;
  const std::vector<Eigen::Vector2d>* points_ = nullptr;
  KnownBuckets known_;
  double radius_ = 0;                 ///< largest distance of a point from the centre
  std::vector<double> cos_, sin_;
  std::vector<char> built_;           ///< per angle
  std::vector<int> offsets_;          ///< per angle: num_buckets_ + 1 bucket starts
  std::vector<int> sorted_;           ///< per angle: the point indices by bucket (stable)
  std::vector<int> bucket_of_;        ///< scratch: each point's bucket at the angle being built
  std::vector<uint64_t> marks_;       ///< scratch: a query's points as a bit set
};
}  // namespace dvs_line_tracker
