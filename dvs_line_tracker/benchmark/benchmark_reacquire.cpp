// benchmark_reacquire: after a loss, is a correct pose back within 0.3 s (issue 14, part 2)?
// Each of the start-anywhere sweep's scenes (sweep_scene.h) gets one seeded disturbance while
// the tracker is tracking: an event blackout, an occlusion of part of the map, a bump, or the
// map leaving the view (reacquire_evaluation.h), 0.2-1 s long. Prints one row per scene and a
// summary over the scenes that were tracking when it began.
//
//   rosrun dvs_line_tracker benchmark_reacquire [--scenes 192] [--jobs 2] [--scene I] [--params tracker.yaml]
#include "benchmark_stats.h"
#include "benchmark_tool.h"
#include "reacquire_evaluation.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

using namespace dvs_line_tracker;

namespace
{
constexpr double kTargetS = 0.3;

void usage()
{
  std::fprintf(stderr, "usage: benchmark_reacquire [--scenes N (>= 1, default 192)] [--jobs J (1-16, default 2)] "
                       "[--scene I (only scene I)]\n"
                       "       [--params tracker.yaml (tracker parameters, as track_offline --params)]\n"
                       "       [--dump DIR (with --scene: write its disturbed events.txt, groundtruth.txt, calib.txt, map.yaml)]\n");
}

std::string describe(const Disturbance& d)
{
  char buf[96];
  switch (d.kind)
  {
    case DisturbanceKind::kBump:
      std::snprintf(buf, sizeof buf, "bump %.0f deg at %.2f s", d.angle_deg, d.start_s);
      break;
    case DisturbanceKind::kLeaveView:
      std::snprintf(buf, sizeof buf, "leaves the view (%.0f deg) %.2f s at %.2f s", d.angle_deg, d.length_s, d.start_s);
      break;
    default:
      std::snprintf(buf, sizeof buf, "%s %.2f s at %.2f s", disturbanceLabel(d.kind), d.length_s, d.start_s);
  }
  return buf;
}
}  // namespace

int main(int argc, char** argv)
{
  SceneOptions options;
  options.count = 192;
  if (!parseSceneOptions("benchmark_reacquire", argc, argv, options))
  {
    usage();
    return 2;
  }
  const int count = options.count, jobs = options.jobs, only = options.only;
  const std::string& dump = options.dump;
  const LineTrackerParams& params = options.params;
  const std::vector<SweepSceneSpec> specs = sweepSceneSpecs(std::max(count, only + 1));
  const std::vector<int> todo = options.selected();

  if (!dump.empty())
  {
    if (!createOutputFolder("benchmark_reacquire", "--dump", dump))
      return 1;
    try
    {
      const DisturbedScene d = disturbSweepScene(buildReacquireScene(specs[only]), only);
      writeSweepSceneFiles(dump, d.scene, d.events);
      std::printf("wrote %zu events of scene %d (%s, back at %.3f s, edges fire again at %.3f s) to %s\n",
                  d.events.size(), only, describe(d.disturbance).c_str(), d.disturbance.backAt(), d.edges_refire_s,
                  dump.c_str());
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "benchmark_reacquire: %s\n", e.what());
      return 1;
    }
    return 0;
  }
  std::vector<ReacquireResult> results(specs.size());
  std::vector<SweepScene> scenes(specs.size());
  std::vector<std::string> errors(specs.size());
  runScenes(todo, jobs, errors, [&](int i) {
    scenes[i] = buildReacquireScene(specs[i]);
    results[i] = runReacquireScene(scenes[i], i, params);
  });

  std::printf("| # | sensor | lens (hfov, k1) | distance | motion | map | noise | disturbance | tracking before | "
              "edges fire again after it [s] | track kept | correct pose after that [s] | re-inits / false | "
              "tracked from 0.3 s after it (>= 3 edges) | RMS then / distance | CPU [s] |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  int failed = 0, before = 0, back_in_time = 0, kept = 0, false_reinits = 0;
  std::vector<double> delays;
  std::vector<int> late;
  double worst_delay = 0, worst_tracked = 1;
  for (int i : todo)
  {
    const auto& sp = specs[i];
    if (!errors[i].empty())
    {
      ++failed;
      std::printf("| %d | %s | %s | error: %s |\n", i, sensorLabel(sp).c_str(), lensLabel(sp).c_str(), errors[i].c_str());
      continue;
    }
    const auto& s = scenes[i];
    const auto& r = results[i];
    char back[32] = "never", refire[32] = "not before the end";
    if (r.back_after_s >= 0)
      std::snprintf(back, sizeof back, "%.3f", r.back_after_s);
    if (r.edges_refire_s >= 0)
      std::snprintf(refire, sizeof refire, "%.3f", r.edges_refire_s - r.disturbance.backAt());
    std::printf("| %d | %s | %s | %.2f m | %s | %s | %s | %s | %s | %s | %s | %s | %d / %d | %.1f %% | %.2f %% | %.1f |\n", i,
                sensorLabel(sp).c_str(), lensLabel(sp).c_str(), s.distance, motionLabel(sp.motion), mapLabel(sp.map),
                noiseLabel(sp.noise), describe(r.disturbance).c_str(), r.tracking_before ? "yes" : "no", refire,
                r.kept ? "yes" : "no", back, r.reinitializations, r.false_reinitializations, 100 * r.tracked_after,
                100 * r.rms_after_ratio, r.tracker_cpu_s);
    if (only >= 0)
      std::printf("\nlast loss: %s\ninitialiser: %s\n\n", r.last_loss_reason.c_str(), r.init_stats.json().c_str());
    if (!r.tracking_before || r.edges_refire_s < 0)
      continue;
    ++before;
    kept += r.kept ? 1 : 0;
    false_reinits += r.false_reinitializations;
    if (r.back_after_s >= 0)
    {
      delays.push_back(r.back_after_s);
      worst_delay = std::max(worst_delay, r.back_after_s);
    }
    if (r.back_after_s >= 0 && r.back_after_s <= kTargetS)
      ++back_in_time;
    else
      late.push_back(i);
    worst_tracked = std::min(worst_tracked, r.tracked_after);
  }
  std::string late_list;
  for (int i : late)
    late_list += (late_list.empty() ? "" : ", ") + std::to_string(i);
  std::printf("\n**Summary** (%d scenes; judged: %d, tracking when the disturbance began and with the map's edges "
              "firing again before the end): a correct pose (5 %% / 3 deg) back within %.1f s of the edges firing "
              "again in %d / %d (track kept through it in %d); median %.3f s, worst %.3f s%s%s; false "
              "re-initialisations %d; worst tracked fraction from %.1f s after it (>= 3 edges in view) %.1f %%%s\n",
              static_cast<int>(todo.size()) - failed, before, kTargetS, back_in_time, before, kept, median(delays, -1),
              worst_delay, late.empty() ? "" : "; late or never: ", late_list.c_str(), false_reinits, kTargetS,
              100 * (before ? worst_tracked : 0), failed ? " (some scenes could not be built: see the rows)" : "");
  return 0;
}
