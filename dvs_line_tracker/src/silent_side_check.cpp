#include <dvs_line_tracker/silent_side_check.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dvs_line_tracker
{
double sweptArea(const ProjectedSegment& before, const ProjectedSegment& now)
{
  if (!(now.length > 0))
    return 0;
  const double da = now.normal.dot(now.a - before.a), db = now.normal.dot(now.b - before.b);
  const double sum = std::abs(da) + std::abs(db);
  if (!(sum > 0))
    return 0;
  // Same side: a trapezoid; opposite sides: two triangles meeting where the line crossed.
  const double full = (da >= 0) == (db >= 0) ? 0.5 * sum * now.length : 0.5 * (da * da + db * db) / sum * now.length;
  return full * std::min(1.0, now.visible_length / now.length);
}

SilentSideCheck::SilentSideCheck(int num_segments, const std::vector<std::vector<int>>& polygons, double ratio)
  : num_segments_(std::max(num_segments, 0))
  , ratio_(ratio)
  , groups_(polygons)
  , events_(num_segments_, 0)
  , unexplained_(num_segments_, 0)
  , swept_(num_segments_, 0.0)
  , silent_checks_(num_segments_, 0)
  , silent_since_ns_(num_segments_, 0)
  , ring_(static_cast<size_t>(num_segments_) * kSpanChecks)
  , snapshot_ns_(kSpanChecks, 0)
  , swept_px2_(num_segments_, 0.0)
  , summed_px2_(num_segments_, 0.0)
  , span_events_(num_segments_, 0.0)
  , span_unexplained_(num_segments_, 0.0)
{
  if (groups_.empty())
  {
    groups_.emplace_back();
    for (int i = 0; i < num_segments_; ++i)
      groups_.back().push_back(i);
  }
  // Segment indices outside the map are dropped here, once.
  for (auto& group : groups_)
    group.erase(std::remove_if(group.begin(), group.end(), [this](int i) { return i < 0 || i >= num_segments_; }),
                group.end());
  centres_.assign(groups_.size(), Eigen::Vector2d::Zero());
  have_centre_.assign(groups_.size(), 0);
}

void SilentSideCheck::restart()
{
  std::fill(events_.begin(), events_.end(), 0);
  std::fill(unexplained_.begin(), unexplained_.end(), 0);
  std::fill(swept_.begin(), swept_.end(), 0.0);
  std::fill(silent_checks_.begin(), silent_checks_.end(), 0);
  std::fill(have_centre_.begin(), have_centre_.end(), 0);
  head_ = checks_ = 0;
}

bool SilentSideCheck::near(int g, const Eigen::Vector2d& p, const std::vector<ProjectedSegment>& projected) const
{
  // p is near when c + (p - c) / kNearScale lies on the centre's side of every side in front.
  const Eigen::Vector2d c = centres_[g];
  const Eigen::Vector2d q = c + (p - c) / kNearScale;
  for (int i : groups_[g])
  {
    if (static_cast<size_t>(i) >= projected.size() || !projected[i].in_front)
      return false;
    const ProjectedSegment& s = projected[i];
    if (s.normal.dot(q - s.a) * s.normal.dot(c - s.a) < 0)
      return false;
  }
  return true;
}

void SilentSideCheck::countUnexplained(const Eigen::Vector2d& p, const std::vector<ProjectedSegment>& projected)
{
  for (size_t g = 0; g < groups_.size(); ++g)
    if (have_centre_[g] && near(static_cast<int>(g), p, projected))
      for (int i : groups_[g])
        ++unexplained_[i];
}

std::string SilentSideCheck::check(const std::vector<ProjectedSegment>& projected, int64_t t_ns)
{
  if (checks_ > 0 && t_ns - last_snapshot_ns_ < static_cast<int64_t>(kSnapshotS * 1e9))
    return "";
  last_snapshot_ns_ = t_ns;
  const int n = std::min(static_cast<int>(projected.size()), num_segments_);
  // Each side over the span: from the oldest snapshot (kSpanChecks snapshots ago) to now, when
  // it was in view at both ends.
  const bool full = checks_ == kSpanChecks;
  const int newest = full ? (head_ + kSpanChecks - 1) % kSpanChecks : checks_ - 1;  // -1: none yet
  for (int i = 0; i < n; ++i)
  {
    // The area swept since the last snapshot, summed (a side out of view sweeps nothing).
    if (newest >= 0)
    {
      const Snapshot& last = ring_[static_cast<size_t>(i) * kSpanChecks + newest];
      if (last.projected.visible && projected[i].visible)
        swept_[i] += sweptArea(last.projected, projected[i]);
    }
    const Snapshot& old = ring_[static_cast<size_t>(i) * kSpanChecks + head_];
    const bool judged = full && old.projected.visible && projected[i].visible;
    swept_px2_[i] = judged ? sweptArea(old.projected, projected[i]) : 0.0;
    summed_px2_[i] = judged ? swept_[i] - old.swept : 0.0;
    span_events_[i] = judged ? static_cast<double>(events_[i] - old.events) : 0.0;
    span_unexplained_[i] = judged ? static_cast<double>(unexplained_[i] - old.unexplained) : 0.0;
  }
  // The snapshot of now takes the oldest one's place.
  const double span_s = full ? (t_ns - snapshot_ns_[head_]) * 1e-9 : 0.0;
  const int slot = full ? head_ : checks_;
  for (int i = 0; i < n; ++i)
    ring_[static_cast<size_t>(i) * kSpanChecks + slot] = {projected[i], events_[i], unexplained_[i], swept_[i]};
  snapshot_ns_[slot] = t_ns;
  if (full)
    head_ = (head_ + 1) % kSpanChecks;
  else
    ++checks_;
  // Each polygon's centre for the events until the next snapshot: the mean of its visible
  // sides' ends.
  for (size_t g = 0; g < groups_.size(); ++g)
  {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int count = 0;
    for (int i : groups_[g])
      if (i < n && projected[i].visible)
      {
        sum += projected[i].a + projected[i].b;
        count += 2;
      }
    have_centre_[g] = count > 0;
    if (count > 0)
      centres_[g] = sum / count;
  }
  if (!full || !(ratio_ > 0))
    return "";
  for (const auto& group : groups_)
  {
    // The densest side of the polygon that moved and fired enough to be a reference.
    double density = 0;
    for (int i : group)
      if (i < n && span_events_[i] >= kMinReferenceEvents &&
          swept_px2_[i] >= kMinReferenceSweepPx * projected[i].visible_length && summed_px2_[i] > 0)
        density = std::max(density, span_events_[i] / summed_px2_[i]);
    for (int i : group)
    {
      if (i >= n)
        continue;
      if (!projected[i].visible)
      {
        silent_checks_[i] = 0;
        continue;
      }
      // Judged when it moved and its polygon gives a density; then silent or not. Unjudged
      // snapshots (it paused, or no reference fired) neither count nor clear its silence.
      const double expected = density * swept_px2_[i];
      if (!(density > 0) || swept_px2_[i] < kMinSweepPx * projected[i].visible_length || expected < kMinExpectedEvents)
        continue;
      const bool silent = span_events_[i] < ratio_ * expected && span_unexplained_[i] >= kMinUnexplainedShare * expected;
      if (silent && silent_checks_[i] == 0)
        silent_since_ns_[i] = t_ns;
      silent_checks_[i] = silent ? silent_checks_[i] + 1 : 0;
      if (silent_checks_[i] >= kPersistChecks && t_ns - silent_since_ns_[i] >= static_cast<int64_t>(kPersistS * 1e9))
      {
        char buf[320];
        std::snprintf(buf, sizeof(buf),
                      "map segment %d moved %.1f px across the image in %.3f s with %.0f events attributed, %.0f "
                      "expected at its polygon's density (%.2f per px^2), while %.0f events no side explains "
                      "arrived near the polygon, for %.2f s: no edge is where the pose puts it",
                      i, swept_px2_[i] / std::max(1.0, projected[i].visible_length), span_s, span_events_[i], expected,
                      density, span_unexplained_[i], (t_ns - silent_since_ns_[i]) * 1e-9);
        return buf;
      }
    }
  }
  return "";
}
}  // namespace dvs_line_tracker
