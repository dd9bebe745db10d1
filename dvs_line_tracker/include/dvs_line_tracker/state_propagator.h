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
  /// Whether it carries the pose at `t_ns` (a healthy IMU). While not, the tracker behaves as
  /// without a propagator (an event gap makes the pose stale).
  virtual bool active(int64_t t_ns) const = 0;
  /// The longest event-free gap it may bridge [ns].
  virtual int64_t maxBridgeNs() const = 0;
  /// The tracker bridged a gap with it (statistics).
  virtual void noteGapBridged() {}
};
}  // namespace dvs_line_tracker
