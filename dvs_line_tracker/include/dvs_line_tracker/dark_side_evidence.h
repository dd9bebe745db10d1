#pragma once
// Which side of each tracked edge is dark, learned from the events: the evidence is the sum, over
// attributed events, of polarity (+-1) x the normal displacement, at the event, of the projected
// line since the segment's previous event (ON events: the bright side gains pixels, i.e. the edge
// moves towards its dark side). Pooled per polygon (> 0: dark inside; segments of a polygon with
// a uniform inside share it, so edges that have barely moved yet are corrected consistently); per
// segment for segments in no polygon (> 0: dark along +normal). The edge model's offset is applied
// towards the bright side once the evidence is trusted.
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/segment_attribution.h>

#include <Eigen/Core>

#include <vector>

namespace dvs_line_tracker
{
class DarkSideEvidence
{
public:
  explicit DarkSideEvidence(const LineMap& map);

  /// Tracking (re)starts with these projections as every segment's previous one.
  void restart(const std::vector<ProjectedSegment>& projected)
  {
    last_projection_ = projected;
    updateInsides(projected);
  }
  /// Which side of each segment its polygon's inside lies on, from these projections (the side
  /// of the projected centroid of its corners). It changes only when a polygon's projection turns
  /// over (seen edge-on), so it is refreshed at every quality check, not per event.
  void updateInsides(const std::vector<ProjectedSegment>& projected);
  /// Forget the evidence.
  void clear();

  /// The event position `p` attributed to segment `i`, moved `edge_offset` px towards the
  /// segment's bright side (unchanged until the evidence is trusted); updates the evidence.
  Eigen::Vector2d correct(const Eigen::Vector2d& p, bool polarity, int i, double edge_offset,
                          const std::vector<ProjectedSegment>& projected);

private:
  const LineMap& map_;
  std::vector<double> score_;                   ///< per polygon, then per segment (index polygons + segment)
  std::vector<int> segment_polygon_;            ///< first polygon holding the segment, -1 if none
  std::vector<double> inside_along_normal_;     ///< per segment: +1 when its polygon's inside lies along +normal (no polygon: +1)
  std::vector<ProjectedSegment> last_projection_;  ///< the segment's projection at its previous event
};
}  // namespace dvs_line_tracker
