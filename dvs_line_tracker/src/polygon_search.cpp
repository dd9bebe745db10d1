#include <dvs_line_tracker/polygon_search.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace dvs_line_tracker
{
double ImagePolygon::perimeter() const
{
  double p = 0;
  for (size_t k = 0; k < corners.size(); ++k)
    p += (corners[(k + 1) % corners.size()] - corners[k]).norm();
  return p;
}

double ImagePolygon::signedArea() const
{
  double a = 0;
  for (size_t k = 0; k < corners.size(); ++k)
  {
    const auto& p = corners[k];
    const auto& q = corners[(k + 1) % corners.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return a / 2;
}

bool sameCorners(const ImagePolygon& a, const ImagePolygon& b)
{
  if (a.corners.size() != b.corners.size() || a.open != b.open)
    return false;
  for (const auto& p : a.corners)
  {
    bool near = false;
    for (const auto& q : b.corners)
      near |= (p - q).squaredNorm() < 0.25;
    if (!near)
      return false;
  }
  return true;
}

bool intersectLines(const ImageSegment& a, const ImageSegment& b, Eigen::Vector2d& point)
{
  const Eigen::Vector2d da = a.p1 - a.p0, db = b.p1 - b.p0;
  const double denom = da.x() * db.y() - da.y() * db.x();
  if (std::abs(denom) < 1e-9 * da.norm() * db.norm())
    return false;
  const Eigen::Vector2d w = b.p0 - a.p0;
  const double t = (w.x() * db.y() - w.y() * db.x()) / denom;
  point = a.p0 + t * da;
  return true;
}

namespace
{
/// A segment as a side run from `near_end` to `far_end`; its direction and length are computed
/// once (the search asks for them at every pair it tests: meets() was most of a noisy scene's
/// detection attempts).
struct Oriented
{
  Oriented(int id_, const Eigen::Vector2d& near, const Eigen::Vector2d& far, int end_)
    : id(id_), near_end(near), far_end(far), end(end_), unit((far - near).normalized()), len((far - near).norm())
  {
  }
  int id;
  Eigen::Vector2d near_end, far_end;
  int end = 0;  ///< 0: near_end is the segment's p0, 1: its p1
  const Eigen::Vector2d& dir() const { return unit; }
  double length() const { return len; }

private:
  Eigen::Vector2d unit;
  double len;
};

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

class Search
{
public:
  Search(const std::vector<ImageSegment>& segs, int n, const PolygonSearchParams& p) : segs_(segs), n_(n), p_(p)
  {
    chain_length_ = n;
    cos_min_ = std::cos(p.max_turn_angle_deg * M_PI / 180.0);
    cos_max_ = std::cos(p.min_turn_angle_deg * M_PI / 180.0);
    cos_outside_min_ = std::cos(p.outside_max_turn_angle_deg * M_PI / 180.0);
    cos_outside_max_ = std::cos(p.outside_min_turn_angle_deg * M_PI / 180.0);
    order_.resize(segs.size());
    std::iota(order_.begin(), order_.end(), 0);
    std::stable_sort(order_.begin(), order_.end(), [&](int a, int b) { return segs[a].length() > segs[b].length(); });
    used_.assign(segs.size(), false);
    // The sides that may follow each oriented side, found once per search: the recursion asks
    // for them at every node (meets() was a third of the initialisation's time in scenes with
    // many segments).
    next_sides_.resize(2 * segs.size());
    next_known_.assign(2 * segs.size(), 0);
  }

  /// Search open polygons (n - 1 sides whose outer ends reach the border of the image box).
  void setOpen(double width, double height, double border_px)
  {
    open_ = true;
    chain_length_ = n_ - 1;
    setView({width, height, border_px});
  }

  /// Corners beyond the border of this image need not lie near the ends of sides that reach it.
  void setView(const ImageView& view)
  {
    view_ = view;
    std::fill(next_known_.begin(), next_known_.end(), 0);  // meets() depends on the view
  }

  /// The segments from index `first_bridge` on are bridges (bridgeBorderSegments): every
  /// polygon uses exactly one of them.
  void setBridges(int first_bridge) { first_bridge_ = first_bridge; }

  /// Collect up to `max` polygons with distinct segment sets.
  void runAll(std::vector<ImagePolygon>& found, int max)
  {
    collect_ = &found;
    max_ = max;
    ImagePolygon dummy;
    run(dummy);
  }

  bool run(ImagePolygon& out)
  {
    for (int id : order_)
      for (int end = 0; end < 2 && !isBridge(id); ++end)  // a bridge joins inner ends: never an outer side
      {
        const auto& s = segs_[id];
        Oriented first{id, end == 0 ? s.p0 : s.p1, end == 0 ? s.p1 : s.p0, end};
        chain_.assign(1, first);
        used_[id] = true;
        const bool found = extend(out);
        used_[id] = false;
        if (found)
          return true;
        if (steps_ > p_.max_steps)
          return false;
      }
    return false;
  }

private:
  bool isBridge(int id) const { return first_bridge_ >= 0 && id >= first_bridge_; }

  int bridgesInChain() const
  {
    int n = 0;
    for (const auto& side : chain_)
      n += isBridge(side.id) ? 1 : 0;
    return n;
  }

  /// The complete chain turns outside [outside_min, outside_max] at one of its corners at least.
  bool hasTurnOutside() const
  {
    if (p_.outside_min_turn_angle_deg <= 0.0 && p_.outside_max_turn_angle_deg >= 180.0)
      return true;
    const int corners = open_ ? chain_length_ - 1 : chain_length_;
    for (int k = 0; k < corners; ++k)
    {
      const double c = chain_[k].dir().dot(chain_[(k + 1) % chain_length_].dir());
      if (c < cos_outside_min_ || c > cos_outside_max_)
        return true;
    }
    return false;
  }

  bool turnOk(const Oriented& a, const Oriented& b) const
  {
    const double c = a.dir().dot(b.dir());
    return c >= cos_min_ && c <= cos_max_ && cross(a.dir(), b.dir()) > 0;
  }

  /// Side `a` is followed by side `b`: they turn the right way and their lines meet at a corner
  /// beyond the middle of both, within the allowed gap of `a`'s far end and of `b`'s near end
  /// (segments of slowly moving edges often stop short of the corner).
  bool meets(const Oriented& a, const Oriented& b, Eigen::Vector2d* corner_out, double* gap_out = nullptr) const
  {
    const double gap = p_.corner_proximity_ratio * (a.length() + b.length()) + 3.0;
    const bool a_hidden = view_.known() && atBorder(a.far_end), b_hidden = view_.known() && atBorder(b.near_end);
    if ((!(a_hidden && b_hidden) && (b.near_end - a.far_end).norm() > 2 * gap) || !turnOk(a, b))
      return false;
    Eigen::Vector2d corner;
    if (!intersectLines({a.near_end, a.far_end, 0}, {b.near_end, b.far_end, 0}, corner))
      return false;
    if ((corner - a.near_end).dot(a.dir()) < 0.5 * a.length() || (b.far_end - corner).dot(b.dir()) < 0.5 * b.length())
      return false;
    // A corner beyond the image border: the part of a side between its end at the border and
    // the corner is hidden, not missing evidence (a corner out of view at the start).
    const double beyond = view_.known() ? outsideDistance(corner) : 0.0;
    const bool out_of_view = beyond > view_.border_px && beyond <= std::max(view_.width, view_.height);
    const double gap_a = out_of_view && a_hidden ? 0.0 : (corner - a.far_end).norm();
    const double gap_b = out_of_view && b_hidden ? 0.0 : (corner - b.near_end).norm();
    if (gap_a > gap || gap_b > gap)
      return false;
    if (corner_out)
      *corner_out = corner;
    if (gap_out)
      *gap_out = gap_a + gap_b;
    return true;
  }

  /// Distance of `p` outside the image box (0 inside).
  double outsideDistance(const Eigen::Vector2d& p) const
  {
    const double dx = std::max({0.0, -p.x(), p.x() - (view_.width - 1)});
    const double dy = std::max({0.0, -p.y(), p.y() - (view_.height - 1)});
    return std::hypot(dx, dy);
  }

  /// The corner where side `a` meets side `b`, appended to `poly` with its gap.
  bool addCorner(const Oriented& a, const Oriented& b, ImagePolygon& poly) const
  {
    Eigen::Vector2d corner;
    double gap = 0;
    if (!meets(a, b, &corner, &gap))
      return false;
    poly.gap_px += gap;
    poly.corners.push_back(corner);
    return true;
  }

  bool closes(ImagePolygon& out) const
  {
    ImagePolygon poly;
    for (int k = 0; k < n_; ++k)
    {
      if (!addCorner(chain_[(k + n_ - 1) % n_], chain_[k], poly))
        return false;
      poly.segment_ids.push_back(chain_[k].id);
    }
    for (int k = 0; k < n_; ++k)
      if ((poly.corners[(k + 1) % n_] - poly.corners[k]).norm() < p_.min_side_px)
        return false;
    out = poly;
    return true;
  }

  bool atBorder(const Eigen::Vector2d& p) const
  {
    return atImageBorder(p, view_.width, view_.height, view_.border_px);
  }

  bool opens(ImagePolygon& out) const
  {
    ImagePolygon poly;
    poly.open = true;
    for (int k = 0; k < chain_length_; ++k)
    {
      if (k + 1 < chain_length_ && !addCorner(chain_[k], chain_[k + 1], poly))
        return false;
      poly.segment_ids.push_back(chain_[k].id);
    }
    poly.bridged = first_bridge_ >= 0;
    poly.open_first = chain_.front().near_end;
    poly.open_last = chain_.back().far_end;
    if (!atBorder(poly.open_first) || !atBorder(poly.open_last))
      return false;
    for (size_t k = 0; k + 1 < poly.corners.size(); ++k)
      if ((poly.corners[k + 1] - poly.corners[k]).norm() < p_.min_side_px)
        return false;
    if ((poly.open_first - poly.corners.front()).norm() < 0.5 * p_.min_side_px ||
        (poly.open_last - poly.corners.back()).norm() < 0.5 * p_.min_side_px)
      return false;
    out = poly;
    return true;
  }

  bool extend(ImagePolygon& out)
  {
    if (++steps_ > p_.max_steps)
      return false;
    if (static_cast<int>(chain_.size()) == chain_length_)
    {
      if ((first_bridge_ >= 0 && bridgesInChain() != 1) || !hasTurnOutside() || !(open_ ? opens(out) : closes(out)))
        return false;
      if (!collect_)
        return true;
      std::vector<int> ids = out.segment_ids;
      std::sort(ids.begin(), ids.end());
      for (auto& f : *collect_)
      {
        std::vector<int> other = f.segment_ids;
        std::sort(other.begin(), other.end());
        if (other == ids)
          return false;
        // Other pieces of the same lines (splitAtJunctions) give the same corners: one polygon,
        // the one whose sides meet best.
        if (sameCorners(f, out))
        {
          if (out.gap_px < f.gap_px)
            f = out;
          return false;
        }
      }
      collect_->push_back(out);
      return static_cast<int>(collect_->size()) >= max_;
    }
    const Oriented cur = chain_.back();
    const bool bridge_used = first_bridge_ >= 0 && bridgesInChain() > 0;
    const std::vector<std::pair<double, Oriented>>& next_sides = nextSides(cur);
    for (const auto& candidate : next_sides)
    {
      if (used_[candidate.second.id] || (bridge_used && isBridge(candidate.second.id)))
        continue;
      chain_.push_back(candidate.second);
      used_[candidate.second.id] = true;
      const bool found = extend(out);
      used_[candidate.second.id] = false;
      chain_.pop_back();
      if (found)
        return true;
    }
    return false;
  }

  /// Every oriented side that `cur` meets, closest corner first (a long segment nearby must not
  /// win over the side that really meets this one; ties in the order of order_), whether used
  /// or not: extend() skips the used ones (filtering after a stable sort keeps the same order).
  const std::vector<std::pair<double, Oriented>>& nextSides(const Oriented& cur)
  {
    const size_t k = static_cast<size_t>(2 * cur.id + cur.end);
    std::vector<std::pair<double, Oriented>>& next = next_sides_[k];
    if (next_known_[k])
      return next;
    next.clear();
    for (int id : order_)
    {
      if (id == cur.id)
        continue;
      const auto& s = segs_[id];
      for (int end = 0; end < 2; ++end)
      {
        Oriented side{id, end == 0 ? s.p0 : s.p1, end == 0 ? s.p1 : s.p0, end};
        Eigen::Vector2d corner;
        double gap = 0;
        if (meets(cur, side, &corner, &gap))
          next.emplace_back(gap, side);
      }
    }
    std::stable_sort(next.begin(), next.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    next_known_[k] = 1;
    return next;
  }

  const std::vector<ImageSegment>& segs_;
  int n_;
  PolygonSearchParams p_;
  double cos_min_, cos_max_;
  double cos_outside_min_, cos_outside_max_;
  std::vector<int> order_;
  std::vector<bool> used_;
  std::vector<Oriented> chain_;
  int steps_ = 0;
  int chain_length_ = 0;
  bool open_ = false;
  int first_bridge_ = -1;
  ImageView view_;
  std::vector<ImagePolygon>* collect_ = nullptr;
  int max_ = 1;
  std::vector<std::vector<std::pair<double, Oriented>>> next_sides_;  ///< per oriented side (2 id + end): nextSides()
  std::vector<char> next_known_;
};
}  // namespace

std::vector<ImagePolygon> findOpenPolygons(const std::vector<ImageSegment>& segments, int num_sides,
                                           const PolygonSearchParams& params, double width, double height,
                                           double border_px, int max_polygons, int first_bridge)
{
  std::vector<ImagePolygon> found;
  if (num_sides < 4 || static_cast<int>(segments.size()) < num_sides - 1 || max_polygons < 1 ||
      first_bridge >= static_cast<int>(segments.size()))
    return found;
  Search search(segments, num_sides, params);
  search.setOpen(width, height, border_px);
  search.setBridges(first_bridge);
  search.runAll(found, max_polygons);
  std::stable_sort(found.begin(), found.end(),
                   [](const ImagePolygon& a, const ImagePolygon& b) { return a.gap_px < b.gap_px; });
  return found;
}

bool atImageBorder(const Eigen::Vector2d& p, double width, double height, double border_px)
{
  return p.x() < border_px || p.y() < border_px || p.x() > width - 1 - border_px || p.y() > height - 1 - border_px;
}

std::vector<ImageSegment> bridgeBorderSegments(const std::vector<ImageSegment>& segments,
                                               const PolygonSearchParams& params, double width, double height,
                                               double border_px)
{
  // The inner ends of segments that run out of view with their other end.
  std::vector<Eigen::Vector2d> inner;
  for (const auto& s : segments)
  {
    const bool b0 = atImageBorder(s.p0, width, height, border_px), b1 = atImageBorder(s.p1, width, height, border_px);
    if (b0 != b1 && s.length() >= params.min_side_px)
      inner.push_back(b0 ? s.p1 : s.p0);
  }
  std::vector<ImageSegment> out = segments;
  for (size_t i = 0; i < inner.size(); ++i)
    for (size_t j = i + 1; j < inner.size(); ++j)
      if ((inner[j] - inner[i]).norm() >= params.min_side_px)
        out.push_back({inner[i], inner[j], 0});
  return out;
}

std::vector<ImageSegment> splitAtJunctions(const std::vector<ImageSegment>& segments,
                                           const PolygonSearchParams& params)
{
  std::vector<ImageSegment> out = segments;
  const size_t max_total = 3 * segments.size();
  const double cos_limit = std::cos(params.min_turn_angle_deg * M_PI / 180.0);
  std::vector<int> order(segments.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return segments[a].length() > segments[b].length(); });
  std::vector<double> cuts;
  for (int i : order)
  {
    const ImageSegment& a = segments[i];
    const double len_a = a.length();
    if (len_a < 2 * params.min_side_px)
      continue;
    const Eigen::Vector2d dir_a = (a.p1 - a.p0) / len_a;
    cuts.clear();
    for (size_t j = 0; j < segments.size(); ++j)
    {
      const ImageSegment& b = segments[j];
      const double len_b = b.length();
      if (static_cast<int>(j) == i || len_b < 1e-9 || std::abs(dir_a.dot((b.p1 - b.p0) / len_b)) > cos_limit)
        continue;
      Eigen::Vector2d x;
      if (!intersectLines(a, b, x))
        continue;
      const double t = (x - a.p0).dot(dir_a);
      if (t < params.min_side_px || t > len_a - params.min_side_px)
        continue;
      const double gap = params.corner_proximity_ratio * len_b + 3.0;
      if (std::min((x - b.p0).norm(), (x - b.p1).norm()) > gap)
        continue;
      cuts.push_back(t);
    }
    if (cuts.empty())
      continue;
    std::sort(cuts.begin(), cuts.end());
    // Junctions closer than 3 px are one; pieces: from each end to each junction, and between
    // neighbouring junctions.
    std::vector<double> at{cuts.front()};
    for (double t : cuts)
      if (t - at.back() > 3.0)
        at.push_back(t);
    auto piece = [&](double t0, double t1) {
      if (t1 - t0 < params.min_side_px || out.size() >= max_total)
        return;
      ImageSegment s;
      s.p0 = a.p0 + t0 * dir_a;
      s.p1 = a.p0 + t1 * dir_a;
      s.num_events = static_cast<int>(a.num_events * (t1 - t0) / len_a);
      out.push_back(s);
    };
    for (size_t k = 0; k < at.size(); ++k)
    {
      piece(0.0, at[k]);
      piece(at[k], len_a);
      if (k + 1 < at.size())
        piece(at[k], at[k + 1]);
    }
  }
  return out;
}

std::vector<ImageSegment> joinCollinearSegments(const std::vector<ImageSegment>& segments)
{
  constexpr double kJoinAngleDeg = 10.0, kJoinDistancePx = 2.0;
  const double cos_limit = std::cos(kJoinAngleDeg * M_PI / 180.0);
  struct Join
  {
    double gap;
    ImageSegment segment;
  };
  std::vector<Join> joins;
  auto lineDistance = [](const ImageSegment& s, const Eigen::Vector2d& p) { return std::abs(cross(s.direction(), p - s.p0)); };
  for (size_t i = 0; i < segments.size(); ++i)
    for (size_t j = i + 1; j < segments.size(); ++j)
    {
      const ImageSegment& a = segments[i];
      const ImageSegment& b = segments[j];
      const double len_a = a.length(), len_b = b.length();
      if (len_a < 1e-9 || len_b < 1e-9)
        continue;
      const Eigen::Vector2d dir = a.direction();
      if (std::abs(dir.dot(b.direction())) < cos_limit)
        continue;
      // Positions along a's direction: a spans [0, len_a]; b must lie wholly before or after it.
      const double t0 = dir.dot(b.p0 - a.p0), t1 = dir.dot(b.p1 - a.p0);
      const double lo = std::min(t0, t1), hi = std::max(t0, t1);
      const Eigen::Vector2d& b_lo = t0 <= t1 ? b.p0 : b.p1;
      const Eigen::Vector2d& b_hi = t0 <= t1 ? b.p1 : b.p0;
      const bool after = lo >= len_a, before = hi <= 0;
      const double gap = after ? lo - len_a : -hi;
      if (!(after || before) || gap > std::min(len_a, len_b))
        continue;
      Join join;
      join.gap = gap;
      join.segment.p0 = after ? a.p0 : b_lo;
      join.segment.p1 = after ? b_hi : a.p1;
      // The inner ends lie on the line between the outer ends (the pieces' own directions,
      // extrapolated over the whole side, would amplify their angle noise).
      if (join.segment.length() < 1e-9 || lineDistance(join.segment, after ? a.p1 : a.p0) > kJoinDistancePx ||
          lineDistance(join.segment, after ? b_lo : b_hi) > kJoinDistancePx)
        continue;
      join.segment.num_events = a.num_events + b.num_events;
      joins.push_back(join);
    }
  std::stable_sort(joins.begin(), joins.end(), [](const Join& x, const Join& y) { return x.gap < y.gap; });
  std::vector<ImageSegment> out = segments;
  for (size_t k = 0; k < joins.size() && k < segments.size(); ++k)
    out.push_back(joins[k].segment);
  return out;
}

bool findPolygon(const std::vector<ImageSegment>& segments, int num_sides, const PolygonSearchParams& params,
                 ImagePolygon& polygon)
{
  const std::vector<ImagePolygon> found = findPolygons(segments, num_sides, params, 8);
  if (found.empty())
    return false;
  polygon = found.front();
  return true;
}

std::vector<ImagePolygon> findPolygons(const std::vector<ImageSegment>& segments, int num_sides,
                                       const PolygonSearchParams& params, int max_polygons, int search_polygons,
                                       const ImageView& view)
{
  std::vector<ImagePolygon> found;
  if (num_sides < 3 || static_cast<int>(segments.size()) < num_sides || max_polygons < 1)
    return found;
  Search search(segments, num_sides, params);
  search.setView(view);
  search.runAll(found, std::max(max_polygons, search_polygons));
  std::stable_sort(found.begin(), found.end(),
                   [](const ImagePolygon& a, const ImagePolygon& b) { return a.gap_px < b.gap_px; });
  if (static_cast<int>(found.size()) > max_polygons)
    found.resize(max_polygons);
  return found;
}
}  // namespace dvs_line_tracker
