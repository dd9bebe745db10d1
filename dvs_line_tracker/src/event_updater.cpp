#include <dvs_line_tracker/event_updater.h>

#include <algorithm>
#include <cmath>

namespace dvs_line_tracker
{
EventUpdater::EventUpdater(const TrackingGeometry& geometry, const LineTrackerParams& params)
  : geometry_(geometry), params_(params), dark_side_(geometry.map)
{
}

void EventUpdater::reset()
{
  dark_side_.clear();
  num_changed_ = events_since_solve_ = 0;
  offset_since_solve_ = 0;
  held_steps_ = 0;
  rate_clock_started_ = false;
  solves_ = factorizations_ = 0;
  factor_.valid = false;
  std::fill(changed_flag_.begin(), changed_flag_.end(), 0);
  round_robin_ = 0;
  updates_since_normalize_ = 0;
}

int EventUpdater::start(EstimatorState& state, const Pose& pose)
{
  state.pose = pose;
  state.damping = params_.estimator.damping;
  state.partial_view = false;
  state.x_accumulated.setZero();
  project(state, true);
  dark_side_.restart(state.projected);
  int visible = 0;
  for (size_t i = 0; i < state.projected.size(); ++i)
  {
    state.buffers[i].clear();
    const ProjectedSegment& s = state.projected[i];
    if (!s.visible)
      continue;
    ++visible;
    // Seed the buffer with points spread along the visible part of the projected segment.
    Eigen::Vector2d ca, cb;
    geometry_.clippedSegment(s, &ca, &cb);
    const int k = state.buffers[i].capacity();
    for (int j = 0; j < k; ++j)
      state.buffers[i].insert(ca + (cb - ca) * ((j + 0.5) / k), s);
  }
  for (size_t i = 0; i < state.projected.size(); ++i)
    relinearize(state, static_cast<int>(i));
  linearized_at_.assign(state.projected.size(), solves_);
  // Nothing pending for the next solve (the buffers were just seeded and linearised).
  changed_flag_.assign(state.projected.size(), 0);
  changed_list_.assign(state.projected.size(), 0);
  num_changed_ = events_since_solve_ = 0;
  offset_since_solve_ = 0;
  held_steps_ = 0;
  rate_clock_started_ = false;
  factor_.valid = false;
  return visible;
}

bool EventUpdater::update(EstimatorState& state, const Eigen::Vector2d& p, bool polarity, double edge_offset,
                          int64_t t_ns, int* attributed_to, bool may_hold)
{
  int segs[2];
  const int n =
      attributeEvent(p, state.projected.data(), static_cast<int>(state.projected.size()), params_.attribution, segs);
  if (attributed_to)
  {
    attributed_to[0] = n > 0 ? segs[0] : -1;
    attributed_to[1] = n > 1 ? segs[1] : -1;
  }
  if (n == 0)
    return false;
  for (int i = 0; i < n; ++i)
  {
    SegmentBuffer& buffer = state.buffers[segs[i]];
    const int slot = buffer.insert(dark_side_.correct(p, polarity, segs[i], edge_offset, state.projected),
                                   state.projected[segs[i]], params_.attribution.max_orthogonal_px,
                                   params_.attribution.max_parallel_px,
                                   params_.buffer_motion_px > 0 ? params_.buffer_motion_px : 1e300,
                                   params_.estimator.huber_px);
    offset_since_solve_ += std::abs(buffer.offset(slot));
    if (!changed_flag_[segs[i]])
    {
      changed_flag_[segs[i]] = 1;
      changed_list_[num_changed_++] = segs[i];
    }
  }
  if (++events_since_solve_ >= params_.solve_every_events)
  {
    // Events on their lines carry little news: their steps are taken with the next solve.
    if (may_hold && offset_since_solve_ < params_.solve_min_offset_px)
      ++held_steps_;
    else if (solveAllowed(t_ns))
    {
      noteSolve();
      step(state, changed_list_.data(), num_changed_, 1 + held_steps_);
      for (int i = 0; i < num_changed_; ++i)
        changed_flag_[changed_list_[i]] = 0;
      num_changed_ = 0;
      events_since_solve_ = held_steps_ = 0;
      offset_since_solve_ = 0;
    }
  }
  return true;
}

bool EventUpdater::solveAllowed(int64_t t_ns)
{
  if (params_.max_solve_rate <= 0)
    return true;
  if (!rate_clock_started_)
  {
    rate_clock_started_ = true;
    rate_clock_ns_ = solve_due_ns_ = t_ns;
  }
  rate_clock_ns_ = std::max(rate_clock_ns_, t_ns);
  return rate_clock_ns_ >= solve_due_ns_ - kSolveBurstNs;
}

void EventUpdater::noteSolve()
{
  ++solves_;
  if (params_.max_solve_rate <= 0)
    return;
  const int64_t period_ns = std::max<int64_t>(1, std::llround(1e9 / params_.max_solve_rate));
  solve_due_ns_ = std::max(solve_due_ns_, rate_clock_ns_) + period_ns;
}

void EventUpdater::project(EstimatorState& state, bool update_visibility) const
{
  geometry_.project(state.pose, update_visibility, state.projected);
  state.projected_at = state.pose;
}

void EventUpdater::relinearize(EstimatorState& state, int i) const
{
  SegmentNormalEquations& eq = state.equations[i];
  const ProjectedSegment& s = state.projected[i];
  if (!s.visible)
    eq.active = false;
  else if (state.projected_at.R_camera_world == state.pose.R_camera_world &&
           state.projected_at.t_camera_world == state.pose.t_camera_world)
    // The projection is of this pose (a visible segment is in front: its pixels are set).
    eq.active = linearizeSegment(geometry_.k, s.pc0, s.pc1, s.a, s.b, state.buffers[i], eq);
  else
  {
    // (Of a segment clipped at the near plane, the clipped part's world points.)
    Eigen::Vector3d p0, p1;
    geometry_.usedEndpoints(static_cast<int>(i), s, p0, p1);
    eq.active = linearizeSegment(geometry_.k, state.pose, p0, p1, state.buffers[i], eq);
  }
  eq.x_lin = state.x_accumulated;
}

void EventUpdater::step(EstimatorState& state, const int* changed, int num_changed, int steps_wanted)
{
  const int n = static_cast<int>(state.equations.size());
  const auto& ep = params_.estimator;
  if (ep.solver == SolverType::kIncremental)
  {
    // Re-linearise, and follow how far the information moved from the factored one: the summed
    // absolute change of each diagonal element (a segment turning active or inactive changes it
    // wholesale).
    const auto relinearizeTracked = [&](int i) {
      const SegmentNormalEquations& eq = state.equations[i];
      const bool was_active = eq.active;
      const Vector6d before = eq.H.diagonal();
      relinearize(state, i);
      linearized_at_[i] = solves_;
      if (eq.active != was_active)
        factor_.valid = false;
      else if (eq.active)
        information_change_ += (eq.H.diagonal() - before).cwiseAbs();
    };
    for (int c = 0; c < num_changed; ++c)
      relinearizeTracked(changed[c]);
    const int steps = std::max(1, std::min(steps_wanted, kMaxStepsPerSolve));
    for (int r = 0; r < ep.extra_relinearizations && n > 1; ++r)
    {
      round_robin_ = (round_robin_ + 1) % n;
      // A segment its own events re-linearised within the last n solves is fresh enough: the
      // round robin keeps every linearisation younger than 2n solves, and the work goes to the
      // segments without events of their own (BENCHMARKS.md: 10 % faster on the DVS128 flip).
      if (solves_ - linearized_at_[round_robin_] < static_cast<uint64_t>(n))
        continue;
      // Segments without events of their own lose their stale events here.
      expireStaleEvents(state, round_robin_);
      relinearizeTracked(round_robin_);
    }
    // A factor serves while the information it was made of changed by less than
    // factor_information_change (a stale factor that under-states the information overshoots),
    // and for at most factor_every_solves steps.
    solves_on_factor_ += steps;
    if (!factor_.valid || solves_on_factor_ >= params_.factor_every_solves ||
        (information_change_.array() > params_.factor_information_change * factor_.information_diagonal.array()).any())
    {
      information_change_.setZero();
      factorDampedInformation(state.equations.data(), n, state.damping, factor_);
      ++factorizations_;
      solves_on_factor_ = 0;
    }
    // The steps held back by solve_min_offset_px are taken now, on the same normal equations:
    // a damped step goes only part of the way in the weakly observed directions, and fewer
    // steps would make the estimate lag there (BENCHMARKS.md, thirtieth session).
    // The normal equations are linear in the increment: the gradient after the first step is
    // the first one plus the summed information times the steps taken (one 6x6 product per
    // step instead of one per segment).
    Vector6d g0, g, delta, total = Vector6d::Zero();
    Matrix6d information;
    bool stepped = false;
    const bool have_gradient =
        steps > 1 ? gradientAndInformationAt(state.equations.data(), n, state.x_accumulated, g0, information)
                  : gradientAt(state.equations.data(), n, state.x_accumulated, g0);
    for (int s = 0; have_gradient && s < steps; ++s)
    {
      g = g0;
      if (s > 0)
        g.noalias() += information * total;
      if (!solveWithFactor(factor_, g, delta))
        break;
      total += delta;
      stepped = true;
    }
    if (stepped)
    {
      state.pose.applyCameraIncrement(total);
      state.x_accumulated += total;
    }
  }
  else
  {
    for (int it = 0; it < ep.full_iterations; ++it)
    {
      for (int i = 0; i < n; ++i)
        relinearize(state, i);
      Vector6d delta;
      if (!solveStep(state.equations.data(), n, state.x_accumulated, state.damping, delta))
        break;
      state.pose.applyCameraIncrement(delta);
      state.x_accumulated += delta;
      project(state, false);
      if (delta.squaredNorm() < 1e-16)
        break;
    }
  }
  if (++updates_since_normalize_ >= 4096)
  {
    state.pose.normalize();
    updates_since_normalize_ = 0;
  }
  // Visibility (clipping) is refreshed by refresh(); per event only the projection.
  project(state, false);
}

void EventUpdater::expireStaleEvents(EstimatorState& state, int i) const
{
  if (params_.buffer_motion_px > 0 && state.projected[i].in_front)
    state.buffers[i].expire(state.projected[i], params_.buffer_motion_px);
}

double EventUpdater::partialViewDamping(double attributed_rate_hz) const
{
  // The damping is a prior per event that holds the pose where the last event left it: per
  // second it holds the harder the more events arrive. A slow camera's few events then let the
  // weakly observable pair (lateral translation / tilt) trail its motion: scaled with the event
  // rate below damping_partial_view_rate, the prior holds the pose for a time rather than for a
  // number of events (a slow partial view at 1.2 m lagged by 5 cm / 2 deg; BENCHMARKS.md,
  // thirty-seventh session). Unknown rate (a track just started): the full damping.
  const double base = params_.estimator.damping;
  double partial = std::max(base, params_.damping_partial_view);
  if (params_.damping_partial_view_rate > 0 && attributed_rate_hz >= 0)
    partial = base + (partial - base) * std::min(1.0, attributed_rate_hz / params_.damping_partial_view_rate);
  return partial;
}

void EventUpdater::refresh(EstimatorState& state, double attributed_rate_hz)
{
  project(state, true);
  dark_side_.updateInsides(state.projected);
  // Segments that moved without producing events (e.g. an edge leaving the view) would keep
  // their stale events: drop them here too, not only when the segment receives an event.
  for (size_t i = 0; i < state.buffers.size(); ++i)
    expireStaleEvents(state, static_cast<int>(i));
  // Part of the map outside the image (or behind the camera): fewer and shorter lines constrain
  // the pose, so its weakly observable directions get the stronger damping.
  bool partial = false;
  for (const auto& s : state.projected)
    partial |= !s.in_front || s.visible_length < s.length - 1.0;
  state.partial_view = partial;
  state.damping = partial ? partialViewDamping(attributed_rate_hz) : params_.estimator.damping;
  // Visibility and damping may have changed: the next solve assembles the information anew.
  factor_.valid = false;
}
}  // namespace dvs_line_tracker
