#include <dvs_line_tracker/line_point_index.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace dvs_line_tracker
{
LinePointIndex::LinePointIndex(int num_angles, double r_max, double bucket_px, const Eigen::Vector2d& centre)
  : num_angles_(num_angles), r_max_(r_max), bucket_px_(bucket_px), centre_(centre)
{
  if (num_angles < 1 || !(r_max > 0) || !(bucket_px > 0))
    throw std::invalid_argument("LinePointIndex: needs >= 1 angle, a positive radius and bucket size");
  num_buckets_ = static_cast<int>(std::ceil(2 * r_max / bucket_px));
  for (int k = 0; k < num_angles; ++k)
  {
    cos_.push_back(std::cos(k * M_PI / num_angles));
    sin_.push_back(std::sin(k * M_PI / num_angles));
  }
  built_.assign(num_angles, 0);
  offsets_.assign(static_cast<size_t>(num_angles) * (num_buckets_ + 1), 0);
}

void LinePointIndex::reset(const std::vector<Eigen::Vector2d>& points, const KnownBuckets& known)
{
  points_ = &points;
  known_ = known;
  if (known_.bins != nullptr &&
      (known_.stride < num_angles_ || known_.capacity < static_cast<int>(points.size()) || known_.start < 0 ||
       known_.start >= std::max(known_.capacity, 1)))
    throw std::invalid_argument("LinePointIndex: known buckets must cover every point at every angle");
  std::fill(built_.begin(), built_.end(), 0);
  if (sorted_.size() < static_cast<size_t>(num_angles_) * points.size())
    sorted_.resize(static_cast<size_t>(num_angles_) * points.size());
  bucket_of_.resize(points.size());
  marks_.resize((points.size() + 63) / 64);
  double r2 = 0;
  for (const auto& p : points)
    r2 = std::max(r2, (p - centre_).squaredNorm());
  radius_ = std::sqrt(r2);
}

int LinePointIndex::anglesBuilt() const
{
  return static_cast<int>(std::count(built_.begin(), built_.end(), 1));
}

int LinePointIndex::bucketAt(int k, const Eigen::Vector2d& p) const
{
  const double r = (p.x() - centre_.x()) * cos_[k] + (p.y() - centre_.y()) * sin_[k];
  return std::clamp(static_cast<int>(std::floor((r + r_max_) / bucket_px_)), 0, num_buckets_ - 1);
}

void LinePointIndex::build(int k)
{
  const std::vector<Eigen::Vector2d>& points = *points_;
  const int n = static_cast<int>(points.size());
  int* offsets = offsets_.data() + static_cast<size_t>(k) * (num_buckets_ + 1);
  std::fill(offsets, offsets + num_buckets_ + 1, 0);
  // The caller's buckets where it has them (a point whose radius the queries compare is bucketed
  // by the same formula; a bucket off by a rounding would still be inside a query's margin).
  const int32_t* known = known_.bins != nullptr ? known_.bins + static_cast<size_t>(known_.start) * known_.stride + k : nullptr;
  int slot = known_.start;
  for (int i = 0; i < n; ++i)
  {
    int b = known != nullptr ? *known : -1;
    if (b < 0 || b >= num_buckets_)
      b = bucketAt(k, points[i]);
    bucket_of_[i] = b;
    ++offsets[b + 1];
    if (known != nullptr)
    {
      if (++slot == known_.capacity)
      {
        slot = 0;
        known = known_.bins + k;
      }
      else
        known += known_.stride;
    }
  }
  std::partial_sum(offsets, offsets + num_buckets_ + 1, offsets);
  int* sorted = sorted_.data() + static_cast<size_t>(k) * n;
  // Stable placement (each bucket keeps the points' order), each bucket's start serving as its
  // write cursor.
  for (int i = 0; i < n; ++i)
    sorted[offsets[bucket_of_[i]]++] = i;
  // The cursors ended at the next bucket's start: shift back.
  for (int b = num_buckets_; b > 0; --b)
    offsets[b] = offsets[b - 1];
  offsets[0] = 0;
  built_[k] = 1;
}

void LinePointIndex::candidates(double theta, double r_lo, double r_hi, double half_width, std::vector<int>& out)
{
  out.clear();
  if (points_ == nullptr || points_->empty())
    return;
  const int n = static_cast<int>(points_->size());
  // Not finite, or so large that folding it by a rounded 2 pi would turn it: nothing to narrow
  // the search by, every point.
  if (!std::isfinite(theta) || !std::isfinite(r_lo) || !std::isfinite(r_hi) || !std::isfinite(half_width) ||
      std::abs(theta) > 1e6)
  {
    out.resize(n);
    std::iota(out.begin(), out.end(), 0);
    return;
  }
  // Fold theta into [0, pi): the radius along theta + pi is the negated radius along theta.
  double t = std::fmod(theta, 2 * M_PI);
  if (t < 0)
    t += 2 * M_PI;
  bool flip = t >= M_PI;
  if (flip)
    t -= M_PI;
  const double step = M_PI / num_angles_;
  long k = std::lround(t / step);
  const double delta = std::abs(t - k * step) + std::abs(half_width);
  if (k >= num_angles_)  // nearest to pi: angle 0 with the radius negated
  {
    k = 0;
    flip = !flip;
  }
  if (delta >= M_PI / 2)
  {
    out.resize(n);
    std::iota(out.begin(), out.end(), 0);
    return;
  }
  // Along a nearby angle a point's radius differs by at most |p - centre| * 2 sin(delta / 2);
  // a small absolute margin covers the rounding of both computations.
  const double margin = radius_ * 2 * std::sin(delta / 2) + 1e-6 * (1 + radius_);
  double lo = r_lo, hi = r_hi;
  if (flip)
  {
    lo = -r_hi;
    hi = -r_lo;
  }
  lo -= margin;
  hi += margin;
  if (!built_[k])
    build(static_cast<int>(k));
  auto bucket = [this](double r) {
    const double b = std::floor((r + r_max_) / bucket_px_);
    return static_cast<int>(std::clamp(b, 0.0, static_cast<double>(num_buckets_ - 1)));
  };
  const int* offsets = offsets_.data() + static_cast<size_t>(k) * (num_buckets_ + 1);
  const int* sorted = sorted_.data() + static_cast<size_t>(k) * n;
  const int* first = sorted + offsets[bucket(lo)];
  const int* last = sorted + offsets[bucket(hi) + 1];
  // Back to the points' order: mark the indices in a bit set, then read it in order.
  std::fill(marks_.begin(), marks_.end(), 0);
  for (const int* i = first; i != last; ++i)
    marks_[*i >> 6] |= uint64_t{1} << (*i & 63);
  out.reserve(last - first);
  for (size_t w = 0; w < marks_.size(); ++w)
    for (uint64_t bits = marks_[w]; bits != 0; bits &= bits - 1)
      out.push_back(static_cast<int>(w * 64) + __builtin_ctzll(bits));
}

void LinePointIndex::nearLine(double theta, double line_r, double distance, std::vector<int>& out)
{
  const double rc = line_r - (centre_.x() * std::cos(theta) + centre_.y() * std::sin(theta));
  candidates(theta, rc - distance, rc + distance, 0.0, out);
}
}  // namespace dvs_line_tracker
