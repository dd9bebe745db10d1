#include <dvs_line_tracker/neighbour_activity.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace dvs_line_tracker
{
NeighbourActivity::NeighbourActivity(int width, int height, int horizon_events, int min_neighbours, bool same_polarity)
  : width_(width)
  , height_(height)
  , stride_(width + 2)
  , horizon_(horizon_events)
  , min_neighbours_(min_neighbours)
  , same_polarity_(same_polarity)
{
  if (width <= 0 || height <= 0 || horizon_events <= 0 || min_neighbours <= 0)
    throw std::invalid_argument("NeighbourActivity: size, horizon and neighbour count must be positive (got " +
                                std::to_string(width) + "x" + std::to_string(height) + ", " +
                                std::to_string(horizon_events) + " events, " + std::to_string(min_neighbours) +
                                " neighbours)");
  reset();
}

void NeighbourActivity::reset()
{
  index_ = 0;
  last_.assign(static_cast<size_t>(stride_) * (height_ + 2), std::numeric_limits<int64_t>::min() / 2);
  if (same_polarity_)
    last_on_ = last_;
}
}  // namespace dvs_line_tracker
