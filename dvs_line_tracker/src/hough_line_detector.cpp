#include <dvs_line_tracker/hough_line_detector.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dvs_line_tracker
{
ImageLine fitLine(const std::vector<Eigen::Vector2d>& points)
{
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points)
    mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& p : points)
    cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const Eigen::Vector2d normal = eig.eigenvectors().col(0);  // smallest eigenvalue
  ImageLine line;
  line.theta = std::atan2(normal.y(), normal.x());
  line.r = normal.dot(mean);
  return line;
}

std::vector<ImageSegment> splitIntoSegments(const std::vector<Eigen::Vector2d>& points, const ImageLine& line,
                                            const HoughParams& params)
{
  const Eigen::Vector2d n = line.normal();
  const Eigen::Vector2d dir(-n.y(), n.x());
  // The positions along the line of the points near it, and the points' indices.
  thread_local std::vector<double> along;
  thread_local std::vector<int> which;
  along.clear();
  which.clear();
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  for (size_t i = 0; i < points.size(); ++i)
    if (std::abs(points[i].dot(n) - line.r) <= params.attribution_distance_px)
    {
      const double s = points[i].dot(dir);
      along.push_back(s);
      which.push_back(static_cast<int>(i));
      lo = std::min(lo, s);
      hi = std::max(hi, s);
    }
  std::vector<ImageSegment> out;
  if (along.empty())
    return out;
  // No sort: buckets max_gap_px wide along the line. Two points of one bucket are never more
  // than a gap apart, so the gaps that split are between the last point of an occupied bucket
  // and the first of the next occupied one (an empty bucket between them is such a gap too).
  const double width = params.max_gap_px;
  const double span = (hi - lo) / std::max(width, 1e-12);
  const int num_buckets = span < 4.0 * along.size() + 64 ? static_cast<int>(span) + 1 : 0;
  struct Bucket
  {
    double min, max;
    int count;
  };
  thread_local std::vector<Bucket> buckets;
  thread_local std::vector<int> bucket_of;
  if (num_buckets > 0)
  {
    buckets.assign(num_buckets, Bucket{std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(), 0});
    bucket_of.resize(along.size());
    for (size_t j = 0; j < along.size(); ++j)
    {
      const int b = std::min(num_buckets - 1, static_cast<int>((along[j] - lo) / width));
      bucket_of[j] = b;
      Bucket& bk = buckets[b];
      bk.min = std::min(bk.min, along[j]);
      bk.max = std::max(bk.max, along[j]);
      ++bk.count;
    }
  }
  else
  {
    // A gap so small against the extent that buckets would outnumber the points: one bucket
    // per point, in order.
    thread_local std::vector<int> order;
    order.resize(along.size());
    for (size_t j = 0; j < order.size(); ++j)
      order[j] = static_cast<int>(j);
    std::sort(order.begin(), order.end(), [](int x, int y) { return along[x] < along[y] || (along[x] == along[y] && x < y); });
    buckets.resize(order.size());
    bucket_of.resize(along.size());
    for (size_t r = 0; r < order.size(); ++r)
    {
      buckets[r] = Bucket{along[order[r]], along[order[r]], 1};
      bucket_of[order[r]] = static_cast<int>(r);
    }
  }
  thread_local std::vector<Eigen::Vector2d> piece;
  const int nb = static_cast<int>(buckets.size());
  int first = -1, count = 0, last = -1;  // the current run of occupied buckets
  auto closeRun = [&]() {
    if (first < 0)
      return;
    const double length = buckets[last].max - buckets[first].min;
    if (count < params.min_segment_events || length < params.min_segment_length_px)
      return;
    piece.clear();
    for (size_t j = 0; j < along.size(); ++j)
      if (bucket_of[j] >= first && bucket_of[j] <= last)
        piece.push_back(points[which[j]]);
    const ImageLine refit = fitLine(piece);
    const Eigen::Vector2d rn = refit.normal();
    Eigen::Vector2d rdir(-rn.y(), rn.x());
    if (rdir.dot(dir) < 0)
      rdir = -rdir;
    double smin = std::numeric_limits<double>::max(), smax = -smin;
    for (const auto& p : piece)
    {
      smin = std::min(smin, p.dot(rdir));
      smax = std::max(smax, p.dot(rdir));
    }
    ImageSegment seg;
    seg.p0 = refit.r * rn + smin * rdir;
    seg.p1 = refit.r * rn + smax * rdir;
    seg.num_events = count;
    if (seg.length() >= params.min_segment_length_px)
      out.push_back(seg);
  };
  for (int b = 0; b < nb; ++b)
  {
    if (buckets[b].count == 0)
      continue;
    if (first >= 0 && buckets[b].min - buckets[last].max > params.max_gap_px)
    {
      closeRun();
      first = -1;
    }
    if (first < 0)
    {
      first = b;
      count = 0;
    }
    count += buckets[b].count;
    last = b;
  }
  closeRun();
  return out;
}

HoughLineDetector::HoughLineDetector(int width, int height, const HoughParams& params, double ideal_radius_px)
  : params_(params)
  , width_(width)
  , height_(height)
  , activity_(std::max(width, 1), std::max(height, 1), std::max(params.neighbour_filter_events, 1),
              std::max(params.neighbour_filter_min, 1), params.neighbour_same_polarity)
{
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("HoughLineDetector: image size must be positive");
  if (!(params.angle_bin_deg > 0 && params.angle_bin_deg <= 90) || !(params.radius_bin_px > 0))
    throw std::invalid_argument("HoughLineDetector: bin sizes must be positive (angle <= 90 deg)");
  if (params.window_events < 1)
    throw std::invalid_argument("HoughLineDetector: window_events must be >= 1");
  if (!(params.max_event_age_s >= 0) || params.max_event_age_s > 1e6)
    throw std::invalid_argument("HoughLineDetector: max_event_age_s must be in [0, 1e6] s");
  max_age_ns_ = static_cast<int64_t>(std::llround(params.max_event_age_s * 1e9));
  num_theta_ = static_cast<int>(std::lround(180.0 / params.angle_bin_deg));
  cx_ = (width - 1) / 2.0;
  cy_ = (height - 1) / 2.0;
  // The radius grid is anchored at the sensor's half diagonal (+4 px); an undistorted image
  // reaching further (barrel distortion) adds whole bins, so the grid does not shift.
  r_max_ = std::hypot(width / 2.0 + 4, height / 2.0 + 4);
  if (ideal_radius_px + 4 > r_max_)
    r_max_ += std::ceil((ideal_radius_px + 4 - r_max_) / params.radius_bin_px) * params.radius_bin_px;
  num_r_ = static_cast<int>(std::ceil(2 * r_max_ / params.radius_bin_px));
  for (int k = 0; k < num_theta_; ++k)
  {
    const double th = k * M_PI / num_theta_;  // bins centred on 0, 7.5, ... deg: axis-aligned edges hit a centre
    cos_.push_back(std::cos(th));
    sin_.push_back(std::sin(th));
  }
  acc_.assign(static_cast<size_t>(num_theta_) * num_r_, 0);
  index_ = LinePointIndex(num_theta_, r_max_, params.radius_bin_px, Eigen::Vector2d(cx_, cy_));
  window_.resize(params.window_events);
  window_pixel_.assign(params.window_events, -1);
  window_t_.assign(params.window_events, 0);
  window_bins_.assign(static_cast<size_t>(params.window_events) * num_theta_, -1);
  evidence_.resize(std::max(params.window_events, params.evidence_events));
  evidence_t_.assign(evidence_.size(), 0);
  in_window_.assign(static_cast<size_t>(width) * height, 0);
}

void HoughLineDetector::reset()
{
  windowChanged();
  std::fill(acc_.begin(), acc_.end(), 0);
  window_head_ = window_count_ = 0;
  evidence_head_ = evidence_count_ = 0;
  std::fill(window_pixel_.begin(), window_pixel_.end(), -1);
  std::fill(in_window_.begin(), in_window_.end(), 0);
  activity_.reset();
}

void HoughLineDetector::curveBins(float x, float y, int32_t* bins) const
{
  const double xc = x - cx_, yc = y - cy_;
  for (int k = 0; k < num_theta_; ++k)
  {
    const double r = xc * cos_[k] + yc * sin_[k];
    const int rb = static_cast<int>((r + r_max_) / params_.radius_bin_px);
    bins[k] = rb >= 0 && rb < num_r_ ? rb : -1;
  }
}

void HoughLineDetector::vote(const int32_t* bins, int increment, std::vector<int>& acc) const
{
  int* row = acc.data();
  for (int k = 0; k < num_theta_; ++k, row += num_r_)
    if (bins[k] >= 0)
      row[bins[k]] += increment;
}

namespace
{
/// The slot `back` entries behind the next write at `head` of a ring of `capacity` slots (with
/// `back` = the count: the oldest entry).
int ringSlot(int head, int back, int capacity) { return (head - back + capacity) % capacity; }
}  // namespace

void HoughLineDetector::expireBefore(int64_t t_ns)
{
  const int capacity = static_cast<int>(window_.size());
  while (window_count_ > 0)
  {
    const int oldest = ringSlot(window_head_, window_count_, capacity);
    if (window_t_[oldest] >= t_ns)
      break;
    vote(slotBins(oldest), -1, acc_);
    windowChanged();
    if (window_pixel_[oldest] >= 0)
      in_window_[window_pixel_[oldest]] = 0;
    window_pixel_[oldest] = -1;
    --window_count_;
  }
  const int evidence_capacity = static_cast<int>(evidence_.size());
  while (evidence_count_ > 0 && evidence_t_[ringSlot(evidence_head_, evidence_count_, evidence_capacity)] < t_ns)
    --evidence_count_;
}

bool HoughLineDetector::addEvent(float x_ideal, float y_ideal, int sx, int sy, int64_t t_ns, bool on)
{
  // Every event, voted or not, moves the age limit on (a pause in the events then empties the
  // window when they resume).
  if (max_age_ns_ > 0)
    expireBefore(t_ns - max_age_ns_);
  // Every event on the sensor counts towards the neighbours' activity; the filter needs its
  // neighbours to have fired shortly before (events without a sensor pixel are not filtered).
  const bool on_sensor = sx >= 0 && sy >= 0 && sx < width_ && sy < height_;
  const bool supported = activity_.add(sx, sy, on);
  if (params_.neighbour_filter && on_sensor && !supported)
    return false;
  const int32_t pixel = on_sensor ? sy * width_ + sx : -1;
  if (params_.unique_pixels && on_sensor && in_window_[pixel])
    return false;  // the pixel already votes
  const int capacity = static_cast<int>(window_.size());
  if (window_count_ == capacity)
  {
    vote(slotBins(window_head_), -1, acc_);
    if (window_pixel_[window_head_] >= 0)
      in_window_[window_pixel_[window_head_]] = 0;
  }
  else
    ++window_count_;
  window_[window_head_] = Eigen::Vector2f(x_ideal, y_ideal);
  window_pixel_[window_head_] = pixel;
  window_t_[window_head_] = t_ns;
  if (on_sensor)
    in_window_[pixel] = 1;
  int32_t* bins = slotBins(window_head_);
  curveBins(x_ideal, y_ideal, bins);
  vote(bins, +1, acc_);
  window_head_ = (window_head_ + 1) % capacity;
  windowChanged();
  evidence_[evidence_head_] = Eigen::Vector2f(x_ideal, y_ideal);
  evidence_t_[evidence_head_] = t_ns;
  evidence_head_ = (evidence_head_ + 1) % static_cast<int>(evidence_.size());
  evidence_count_ = std::min(evidence_count_ + 1, static_cast<int>(evidence_.size()));
  return true;
}

ImageLine HoughLineDetector::binLine(int angle_bin, int radius_bin) const
{
  ImageLine line;
  line.theta = angle_bin * M_PI / num_theta_;
  const double r_centred = (radius_bin + 0.5) * params_.radius_bin_px - r_max_;
  // Shift the origin from the image centre to the top-left pixel.
  line.r = r_centred + cx_ * std::cos(line.theta) + cy_ * std::sin(line.theta);
  return line;
}

std::vector<std::pair<int, int>> HoughLineDetector::candidateBins() const
{
  std::vector<std::pair<int, int>> bins;
  for (int k = 0; k < num_theta_; ++k)
    for (int rb = 0; rb < num_r_; ++rb)
      if (acc_[k * num_r_ + rb] >= params_.vote_threshold)
        bins.emplace_back(k, rb);
  std::sort(bins.begin(), bins.end(), [this](const auto& a, const auto& b) {
    return votes(a.first, a.second) > votes(b.first, b.second);
  });
  return bins;
}

bool HoughLineDetector::radiusPeak(int angle_bin, int radius_bin) const
{
  const int* row = acc_.data() + static_cast<size_t>(angle_bin) * num_r_;
  const int v = row[radius_bin];
  return (radius_bin == 0 || row[radius_bin - 1] <= v) && (radius_bin + 1 == num_r_ || row[radius_bin + 1] <= v);
}

namespace
{
/// The `count` positions of a ring buffer whose next write goes to `head`, oldest first.
std::vector<Eigen::Vector2d> ringPoints(const std::vector<Eigen::Vector2f>& ring, int head, int count)
{
  std::vector<Eigen::Vector2d> points;
  points.reserve(count);
  const int capacity = static_cast<int>(ring.size());
  const int start = ringSlot(head, count, capacity);  // the oldest (the age limit may have dropped some)
  for (int i = 0; i < count; ++i)
    points.push_back(ring[(start + i) % capacity].cast<double>());
  return points;
}
}  // namespace

int64_t HoughLineDetector::timeOfLatest(int k) const
{
  if (window_count_ == 0)
    return 0;
  const int capacity = static_cast<int>(window_.size());
  return window_t_[ringSlot(window_head_, std::max(1, std::min(k, window_count_)), capacity)];
}

std::vector<Eigen::Vector2d> HoughLineDetector::windowPoints() const
{
  return ringPoints(window_, window_head_, window_count_);
}

std::vector<Eigen::Vector2d> HoughLineDetector::evidencePoints() const
{
  return ringPoints(evidence_, evidence_head_, evidence_count_);
}

std::vector<ImageSegment> HoughLineDetector::detectSegments(Pass pass) const
{
  const bool progressive = pass == Pass::kProgressive;
  // A second detection on the same window (the full pass after the progressive one) reuses the
  // window's points, candidates, index and every bin's line and segments found so far.
  if (detected_generation_ != window_generation_ || detected_by_ != this)
  {
    detected_generation_ = window_generation_;
    detected_by_ = this;
    detected_points_ = windowPoints();
    detected_start_ = ringSlot(window_head_, window_count_, static_cast<int>(window_.size()));
    detected_bins_ = candidateBins();
    if (static_cast<int>(detected_bins_.size()) > params_.max_candidates)
      detected_bins_.resize(params_.max_candidates);
    // The index sorts the points by the curve bins they voted with (the same radius grid).
    index_.reset(detected_points_, {window_bins_.data(), num_theta_, detected_start_, static_cast<int>(window_.size())});
    if (bin_results_.size() < detected_bins_.size())
      bin_results_.resize(detected_bins_.size());
    for (size_t j = 0; j < detected_bins_.size(); ++j)
    {
      bin_results_[j].state = BinResult::kUnknown;
      bin_results_[j].split = false;
    }
  }
  const std::vector<Eigen::Vector2d>& points = detected_points_;
  const std::vector<std::pair<int, int>>& bins = detected_bins_;
  const int capacity = static_cast<int>(window_.size());

  const double half_dtheta = 0.5 * M_PI / num_theta_;
  std::vector<ImageSegment> all;
  std::vector<Eigen::Vector2d> support, near;
  std::vector<int> candidates;
  std::vector<ImageLine> processed;
  // The points within the attribution distance of `line`, in the window's order, and their
  // indices in the window.
  std::vector<int> near_index;
  auto pointsNear = [&](const ImageLine& line, std::vector<Eigen::Vector2d>& out) {
    index_.nearLine(line.theta, line.r, params_.attribution_distance_px, candidates);
    out.clear();
    near_index.clear();
    const Eigen::Vector2d ln = line.normal();
    for (const int i : candidates)
      if (std::abs(points[i].dot(ln) - line.r) <= params_.attribution_distance_px)
      {
        out.push_back(points[i]);
        near_index.push_back(i);
      }
  };
  // A bin's line: fitted to the points whose Hough curve passes through the bin (any angle
  // inside it), gated at the attribution distance and refitted once to shed stray support; false
  // when too few points support it.
  auto fitBinLine = [&](int k, int rb, ImageLine& line) {
    const ImageLine centre = binLine(k, rb);
    double cs[3], sn[3], off[3];
    for (int a = 0; a < 3; ++a)
    {
      const double th = centre.theta + (a - 1) * half_dtheta;
      cs[a] = std::cos(th);
      sn[a] = std::sin(th);
      // r measured from the image centre, shifted to compare with centre.r (top-left origin).
      off[a] = -(cx_ * cs[a] + cy_ * sn[a]) + cx_ * std::cos(centre.theta) + cy_ * std::sin(centre.theta);
    }
    const double r_lo = centre.r - params_.radius_bin_px / 2, r_hi = centre.r + params_.radius_bin_px / 2;
    const double r_centred = (rb + 0.5) * params_.radius_bin_px - r_max_;
    index_.candidates(centre.theta, r_centred - params_.radius_bin_px / 2, r_centred + params_.radius_bin_px / 2,
                      half_dtheta, candidates);
    support.clear();
    for (const int i : candidates)
    {
      const Eigen::Vector2d& p = points[i];
      double rmin = std::numeric_limits<double>::max(), rmax = -rmin;
      for (int a = 0; a < 3; ++a)
      {
        const double r = p.x() * cs[a] + p.y() * sn[a] + off[a];
        rmin = std::min(rmin, r);
        rmax = std::max(rmax, r);
      }
      if (rmax >= r_lo && rmin <= r_hi)
        support.push_back(p);
    }
    if (static_cast<int>(support.size()) < params_.min_segment_events)
      return false;
    // Fit, then gate at the attribution distance and refit once to shed stray support.
    line = fitLine(support);
    pointsNear(line, support);
    if (static_cast<int>(support.size()) < params_.min_segment_events)
      return false;
    line = fitLine(support);
    return true;
  };
  // Progressive Hough: the votes of the points a found segment explains leave this copy of the
  // accumulator, and a bin whose remaining votes fall below the threshold is no candidate any
  // more (the other bins of the same edge).
  if (progressive)
  {
    fresh_votes_ = acc_;
    explained_.assign(points.size(), 0);
  }
  for (size_t j = 0; j < bins.size(); ++j)
  {
    const auto [k, rb] = bins[j];
    if (progressive && fresh_votes_[k * num_r_ + rb] < params_.vote_threshold)
      continue;
    if (pass == Pass::kRadiusPeaks && !radiusPeak(k, rb))
      continue;
    BinResult& result = bin_results_[j];
    if (result.state == BinResult::kUnknown)
      result.state = fitBinLine(k, rb, result.line) ? BinResult::kLine : BinResult::kRejected;
    if (result.state == BinResult::kRejected)
      continue;
    const ImageLine& line = result.line;
    // Neighbouring bins usually refit to the same line: split each line once.
    bool seen = false;
    for (const auto& done : processed)
    {
      // (Lines whose offsets differ by 0.5 px either way are never the same: no cosine needed.)
      if (std::abs(done.r - line.r) >= 0.5 && std::abs(done.r + line.r) >= 0.5)
        continue;
      const double c = std::abs(std::cos(done.theta - line.theta));
      const double r_same = std::cos(done.theta - line.theta) > 0 ? done.r : -done.r;
      if (c > std::cos(1.0 * M_PI / 180.0) && std::abs(r_same - line.r) < 0.5)
      {
        seen = true;
        break;
      }
    }
    if (seen)
      continue;
    processed.push_back(line);
    if (progressive || !result.split)
      pointsNear(line, near);
    if (!result.split)
    {
      result.segments = splitIntoSegments(near, line, params_);
      result.split = true;
    }
    const Eigen::Vector2d dir(-line.normal().y(), line.normal().x());
    for (const auto& seg : result.segments)
    {
      all.push_back(seg);
      if (!progressive)
        continue;
      // The segment explains the points near the line along its extent (a pixel beyond).
      double a0 = seg.p0.dot(dir), a1 = seg.p1.dot(dir);
      if (a0 > a1)
        std::swap(a0, a1);
      for (size_t j = 0; j < near.size(); ++j)
      {
        const int i = near_index[j];
        const double along = near[j].dot(dir);
        if (explained_[i] || along < a0 - 1.0 || along > a1 + 1.0)
          continue;
        explained_[i] = 1;
        vote(slotBins((detected_start_ + i) % capacity), -1, fresh_votes_);
      }
    }
  }
  // Remove duplicates (adjacent bins find the same segment): keep the one with most events.
  std::sort(all.begin(), all.end(), [](const ImageSegment& a, const ImageSegment& b) {
    return a.num_events > b.num_events;
  });
  std::vector<ImageSegment> kept;
  for (const auto& s : all)
  {
    bool duplicate = false;
    for (const auto& k : kept)
    {
      const Eigen::Vector2d d = k.direction();
      const Eigen::Vector2d n(-d.y(), d.x());
      if (std::abs(s.direction().dot(d)) < std::cos(5.0 * M_PI / 180.0))
        continue;
      if (std::abs(n.dot(s.p0 - k.p0)) > 3.0 || std::abs(n.dot(s.p1 - k.p0)) > 3.0)
        continue;
      // Overlap along the line.
      const double a0 = 0, a1 = k.length();
      double b0 = d.dot(s.p0 - k.p0), b1 = d.dot(s.p1 - k.p0);
      if (b0 > b1)
        std::swap(b0, b1);
      const double overlap = std::min(a1, b1) - std::max(a0, b0);
      if (overlap > 0.5 * std::min(a1 - a0, b1 - b0))
      {
        duplicate = true;
        break;
      }
    }
    if (!duplicate)
      kept.push_back(s);
  }
  std::sort(kept.begin(), kept.end(), [](const ImageSegment& a, const ImageSegment& b) {
    return a.length() > b.length();
  });
  if (static_cast<int>(kept.size()) > params_.max_segments)
    kept.resize(params_.max_segments);
  return kept;
}
}  // namespace dvs_line_tracker
