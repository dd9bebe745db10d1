#pragma once
// Which events are supported by their neighbours: an event counts as supported when at least
// `min_neighbours` of its 8 neighbouring pixels had an event among the latest `horizon_events`
// events counted. The horizon is in events, not time, so on a sensor firing only background
// activity a pixel's neighbours hold horizon_events / pixels events each on average and the
// supported share of pure noise is fixed whatever the noise rate (binomial: each neighbour fired
// with probability 1 - exp(-horizon / pixels); 2.2 % for two neighbours at the default 500 events
// per 128x128 pixels); an edge's events fire next to each other and are mostly supported.
// Optionally only neighbours of the event's own polarity count: an edge moving one way fires
// one polarity along its length, background activity either, so a same-polarity neighbour
// within the horizon is about half as likely for noise. The background-activity filter of the
// Hough initialisation (hough_line_detector.h) and the loss monitor's test of whether
// unattributed events are structure or noise (loss_monitor.h) both use it.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dvs_line_tracker
{
class NeighbourActivity
{
public:
  /// Throws std::invalid_argument for a non-positive size, horizon or neighbour count.
  /// `same_polarity`: only neighbours whose latest event had the event's polarity count.
  NeighbourActivity(int width, int height, int horizon_events, int min_neighbours, bool same_polarity = false);

  /// Counts an event at pixel (x, y) (ignored, false, outside the sensor); true when it is
  /// supported (judged before it counts itself). `on`: its polarity (used when same_polarity).
  bool add(int x, int y, bool on = false)
  {
    if (x < 0 || y < 0 || x >= width_ || y >= height_)
      return false;
    ++index_;
    const int64_t horizon = index_ - horizon_;
    int64_t* const cell = (same_polarity_ && on ? last_on_ : last_).data() +
                          static_cast<std::size_t>(y + 1) * stride_ + (x + 1);
    int support = 0;
    for (const int64_t* r : {cell - stride_, cell, cell + stride_})
      support += (r[-1] >= horizon) + (r[1] >= horizon) + (r != cell && r[0] >= horizon);
    *cell = index_;
    return support >= min_neighbours_;
  }
  /// Forgets every event.
  void reset();

  int horizonEvents() const { return static_cast<int>(horizon_); }
  bool samePolarity() const { return same_polarity_; }

private:
  int width_, height_, stride_;
  int64_t horizon_;
  int min_neighbours_;
  bool same_polarity_;
  int64_t index_ = 0;
  /// Per pixel, with a border of one that never fires: the index of its latest event (of its
  /// latest OFF event when same_polarity_; then last_on_ holds the ON events').
  std::vector<int64_t> last_, last_on_;
};
}  // namespace dvs_line_tracker
