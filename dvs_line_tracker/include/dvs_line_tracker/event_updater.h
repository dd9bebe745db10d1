#pragma once
#include <vector>
// The per-event measurement update (thesis 4.2.2): attribute an event to the projected map
// segments, buffer it where the edge model puts the edge, and take one damped Gauss-Newton step
// on the buffers' normal equations (pose_estimator.h: incremental or full solver). Also the
// solver policy: which segments are re-linearised per event, how often the damped information
// is factored anew (factor_every_solves; the steps in between reuse its factor with the current
// gradient), the damping in force (stronger while part of the map is out of view), and dropping
// buffered events whose segment moved away.
// A new kind of measurement (e.g. an IMU) gets its own updater beside this one.
#include <dvs_line_tracker/dark_side_evidence.h>
#include <dvs_line_tracker/estimator_state.h>
#include <dvs_line_tracker/tracker_params.h>

#include <cstdint>

namespace dvs_line_tracker
{
class EventUpdater
{
public:
  EventUpdater(const TrackingGeometry& geometry, const LineTrackerParams& params);

  /// Start tracking from `pose`: project, seed every visible segment's buffer with points along
  /// it, linearise. Returns the number of visible segments.
  int start(EstimatorState& state, const Pose& pose);

  /// One event at ideal pixel `p` and time `t_ns` (after start()): attribute it, buffer it
  /// (moved by `edge_offset` towards the bright side), update the pose (once per
  /// solve_every_events attributed events, and at most max_solve_rate times per second of event
  /// time). Returns true when it was attributed. Allocates nothing. `attributed_to` (optional,
  /// two entries): the segments it was attributed to, -1 for none.
  /// `may_hold`: whether solve_min_offset_px may hold the solve back (false while a propagator
  /// moves the pose between events: the projection an event is compared with is then stale).
  bool update(EstimatorState& state, const Eigen::Vector2d& p, bool polarity, double edge_offset, int64_t t_ns,
              int* attributed_to = nullptr, bool may_hold = true);

  /// Refresh what the per-event path leaves stale (called at every quality check): clip the
  /// projections to the image (visibility), drop the stale events of every buffer, and choose
  /// the damping (`attributed_rate_hz`: the attributed events per second lately, negative when
  /// not known yet; below damping_partial_view_rate the partial-view damping falls with it).
  void refresh(EstimatorState& state, double attributed_rate_hz);

  /// Forget learned evidence and counters.
  void reset();

  /// The damping while part of the map is out of view, at `attributed_rate_hz` (negative: not
  /// known).
  double partialViewDamping(double attributed_rate_hz) const;

  /// Gauss-Newton steps taken since construction or reset() (at most one per attributed event).
  uint64_t solves() const { return solves_; }
  /// Factorisations of the damped information since construction or reset(): at least one per
  /// factor_every_solves solves, one whenever the information's diagonal changed by
  /// factor_information_change since the last, and one after every start() and refresh().
  uint64_t factorizations() const { return factorizations_; }

private:
  /// Project the map at state.pose (projected, projected_at).
  void project(EstimatorState& state, bool update_visibility) const;
  void relinearize(EstimatorState& state, int i) const;
  /// A solve that takes `steps_wanted` damped steps (at most kMaxStepsPerSolve) on the same normal equations.
  void step(EstimatorState& state, const int* changed, int num_changed, int steps_wanted);
  static constexpr int kMaxStepsPerSolve = 64;
  void expireStaleEvents(EstimatorState& state, int i) const;

  const TrackingGeometry& geometry_;
  const LineTrackerParams& params_;
  DarkSideEvidence dark_side_;
  int round_robin_ = 0;
  uint64_t updates_since_normalize_ = 0;
  std::vector<char> changed_flag_;  ///< segments with new events since the last solve
  std::vector<int> changed_list_;
  std::vector<uint64_t> linearized_at_;  ///< per segment: solves_ when it was last re-linearised
  int num_changed_ = 0, events_since_solve_ = 0;
  double offset_since_solve_ = 0;  ///< summed |distance| of the events since the last solve from their segments
  int held_steps_ = 0;             ///< solves held back by solve_min_offset_px since the last solve
  // The solve rate limit (a leaky bucket in event time, GCRA): a solve is allowed while the
  // event clock is past solve_due_ns_ - kSolveBurstNs; each solve moves solve_due_ns_ on by one
  // period. Bursts of up to kSolveBurstNs x rate solves pass; the long-run rate is bounded.
  bool solveAllowed(int64_t t_ns);
  void noteSolve();
  static constexpr int64_t kSolveBurstNs = 1000000;
  bool rate_clock_started_ = false;  ///< false after start(): the bucket starts full
  int64_t rate_clock_ns_ = 0;        ///< the latest event time seen (time going back does not move it)
  int64_t solve_due_ns_ = 0;
  uint64_t solves_ = 0;
  DampedFactor factor_;       ///< of the last assembled information (factor_every_solves)
  int solves_on_factor_ = 0;  ///< solves since factor_ was made
  uint64_t factorizations_ = 0;
  Vector6d information_change_ = Vector6d::Zero();  ///< summed |change| of the information's diagonal since factor_
};
}  // namespace dvs_line_tracker
