#pragma once
// The seam for motion between measurements (open_vins' Propagator): before each event's update
// while tracking, the tracker asks its propagator, if it has one, to carry the state to the
// event's time (e.g. integrating an IMU). Without one the pose is held (the thesis's model).
#include <dvs_line_tracker/estimator_state.h>

#include <cstdint>

namespace dvs_line_tracker
{
class StatePropagator
{
public:
  virtual ~StatePropagator() = default;
  /// Carry `state` (its pose) forward to time `t_ns`. Called with non-decreasing times while
  /// tracking; `restart` is called when tracking (re)starts from `state`.
  virtual void propagate(EstimatorState& state, int64_t t_ns) = 0;
  virtual void restart(const EstimatorState& state, int64_t t_ns) = 0;
};
}  // namespace dvs_line_tracker
