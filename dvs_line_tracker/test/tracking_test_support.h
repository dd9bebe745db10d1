#pragma once
// Shared helpers of the end-to-end tests: run the tracker over an event sequence and measure
// it against ground truth.
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_calibration/trajectory_accuracy.h>

#include <string>
#include <vector>

namespace dvs_line_tracker
{
struct TrackingRun
{
  dvs_calibration::Trajectory estimates;  ///< one per pose update
  std::vector<std::pair<double, TrackerState>> transitions;  ///< state changes (time, new state)
  std::vector<std::string> loss_reasons;
  TrackerStats stats;
  TrackerState final_state = TrackerState::kInitializing;
  Pose final_pose;
};

inline TrackingRun runTracker(LineTracker& tracker, const dvs_driver::EventVector& events)
{
  TrackingRun run;
  run.estimates.reserve(events.size());
  TrackerState last = tracker.state();
  for (const auto& e : events)
  {
    if (tracker.processEvent(e))
      run.estimates.push_back({e.t_ns * 1e-9, tracker.pose()});
    if (tracker.state() != last)
    {
      last = tracker.state();
      run.transitions.emplace_back(e.t_ns * 1e-9, last);
      if (last == TrackerState::kLost)
        run.loss_reasons.push_back(tracker.lastLossReason());
    }
  }
  run.stats = tracker.stats();
  run.final_state = tracker.state();
  run.final_pose = tracker.pose();
  return run;
}
}  // namespace dvs_line_tracker
