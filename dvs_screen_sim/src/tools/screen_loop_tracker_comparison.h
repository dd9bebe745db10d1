#pragma once
// benchmark_screen_loop --tracker: the tracker on the emulated screen in the loop vs its
// pure-software run (issue 7), by running simulate, emulate_screen_loop and dvs_line_tracker's
// track_offline as external programs, scored by dvs_calibration::evaluateTrajectory.
namespace dvs_screen_sim
{
/// argv[0] is "--tracker"; returns the process exit status.
int runScreenLoopTrackerComparison(int argc, char** argv);
}  // namespace dvs_screen_sim
