#include <dvs_line_tracker/dark_side_evidence.h>

#include <algorithm>
#include <cmath>

namespace dvs_line_tracker
{
DarkSideEvidence::DarkSideEvidence(const LineMap& map) : map_(map)
{
  const size_t n = map.segments.size();
  score_.assign(map.polygons.size() + n, 0.0);
  segment_polygon_.assign(n, -1);
  for (size_t j = map.polygons.size(); j-- > 0;)
    for (int id : map.polygons[j].segment_ids)
      segment_polygon_[id] = static_cast<int>(j);
  last_projection_.resize(n);
  inside_along_normal_.assign(n, 1.0);
}

void DarkSideEvidence::updateInsides(const std::vector<ProjectedSegment>& projected)
{
  for (size_t i = 0; i < inside_along_normal_.size(); ++i)
  {
    const int poly = segment_polygon_[i];
    if (poly < 0)
      continue;
    // Convex polygons: the inside is the side of the projected centroid of the corners.
    const auto& ids = map_.polygons[poly].segment_ids;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (int id : ids)
      centre += projected[id].a + projected[id].b;
    centre /= 2.0 * ids.size();
    const ProjectedSegment& s = projected[i];
    inside_along_normal_[i] = s.normal.dot(centre - s.a) >= 0 ? 1.0 : -1.0;
  }
}

void DarkSideEvidence::clear() { std::fill(score_.begin(), score_.end(), 0.0); }

Eigen::Vector2d DarkSideEvidence::correct(const Eigen::Vector2d& p, bool polarity, int i, double edge_offset,
                                          const std::vector<ProjectedSegment>& projected)
{
  // Pose jitter is uncorrelated with polarity and averages out of the evidence.
  const ProjectedSegment& s = projected[i];
  ProjectedSegment& last = last_projection_[i];
  // Displacement of the line along +normal at the event: its signed distance then minus now.
  const double moved = last.normal.dot(p - last.a) - s.normal.dot(p - s.a);
  last.a = s.a;
  last.normal = s.normal;
  const int poly = segment_polygon_[i];
  const double inside_along_normal = inside_along_normal_[i];  // updateInsides()
  double& score = score_[poly >= 0 ? poly : static_cast<int>(map_.polygons.size()) + i];
  score += (polarity ? 1.0 : -1.0) * moved * inside_along_normal;
  // Trusted once the edges have moved about a pixel consistently.
  constexpr double kMinScore = 1.0;
  if (std::abs(score) < kMinScore)
    return p;
  const double dark_along_normal = score > 0 ? inside_along_normal : -inside_along_normal;
  return p - dark_along_normal * edge_offset * s.normal;
}
}  // namespace dvs_line_tracker
