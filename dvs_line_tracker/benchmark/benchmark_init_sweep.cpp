// benchmark_init_sweep: does the tracker start (and keep going) wherever a user points the
// camera? Simulates seeded scenes across sensors, lenses, distances, motions, maps, noise and
// partial views (sweep_scene.h) with the suite's software DVS, runs the tracker on each and
// prints one row per scene and a summary.
//
//   rosrun dvs_line_tracker benchmark_init_sweep [--scenes 64] [--jobs 2] [--scene I]
#include "benchmark_tool.h"
#include "benchmark_stats.h"
#include "sweep_evaluation.h"

#include <dvs_line_tracker/body_odometry.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

using namespace dvs_line_tracker;

namespace
{
void usage()
{
  std::fprintf(stderr, "usage: benchmark_init_sweep [--scenes N (>= 1, default 64)] [--jobs J (1-16, default 2)] "
                       "[--scene I (only scene I)]\n"
                       "       [--params tracker.yaml (tracker parameters, as track_offline --params)]\n"
                       "       [--dump DIR (with --scene: write its events.txt, groundtruth.txt, calib.txt, map.yaml)]\n");
}

}  // namespace

int main(int argc, char** argv)
{
  SceneOptions options;
  if (!parseSceneOptions("benchmark_init_sweep", argc, argv, options))
  {
    usage();
    return 2;
  }
  const int count = options.count, jobs = options.jobs, only = options.only;
  const std::string& dump = options.dump;
  const LineTrackerParams& params = options.params;
  std::vector<SweepSceneSpec> specs = sweepSceneSpecs(std::max(count, only + 1));
  const std::vector<int> todo = options.selected();

  if (!dump.empty())
  {
    if (!createOutputFolder("benchmark_init_sweep", "--dump", dump))
      return 1;
    const SweepScene scene = buildSweepScene(specs[only]);
    const dvs_driver::EventVector events = simulateSweepScene(scene);
    try
    {
      writeSweepSceneFiles(dump, scene, events);
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "benchmark_init_sweep: %s\n", e.what());
      return 1;
    }
    std::printf("wrote %zu events of scene %d to %s\n", events.size(), only, dump.c_str());
    return 0;
  }
  std::vector<SweepResult> results(specs.size());
  std::vector<SweepScene> scenes(specs.size());
  std::vector<std::string> errors(specs.size());
  runScenes(todo, jobs, errors, [&](int i) {
    scenes[i] = buildSweepScene(specs[i]);
    results[i] = runSweepScene(scenes[i], params);
  });

  std::printf("| # | sensor | lens (hfov, k1) | distance (coverage) | motion | map | noise | partial | events | "
              "edges fire [s] | first pose after [s] | first pose ok | inits / false | tracked (>= 3 edges) | "
              "RMS [cm / deg] | RMS / distance | CPU tracker / sim [s] |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  int initialized = 0, correct = 0, false_inits = 0, failed = 0;
  std::vector<double> delays;
  double worst_delay = 0, worst_tracked = 1, worst_rms_ratio = 0;
  // The vision-only covariance against the errors, summed over the scenes.
  CovarianceConsistency consistency, consistency_without_lag;
  constexpr double kCoveredEnough = 0.9;
  int covariance_scenes = 0, undercovered = 0, undercovered_without_lag = 0;
  // The partial-view holds (partial_view_grace_s), summed over the scenes.
  uint64_t held = 0, resumed = 0;
  double held_s = 0;
  int held_scenes = 0;
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
    char delay[32] = "none";
    if (r.first_pose_delay_s > -1 || r.first_pose_s >= 0)
      std::snprintf(delay, sizeof delay, "%.3f", r.first_pose_delay_s);
    std::printf("| %d | %s | %s | %.2f m (%.0f %%) | %s | %s | %s | %s | %llu | %.3f | %s | %s | %d / %d | %.1f %% | "
                "%.2f / %.2f | %.2f %% | %.1f / %.1f |\n",
                i, sensorLabel(sp).c_str(), lensLabel(sp).c_str(), s.distance, 100 * s.coverage, motionLabel(sp.motion),
                mapLabel(sp.map), noiseLabel(sp.noise), sp.partial ? "yes" : "no",
                static_cast<unsigned long long>(r.events), r.edges_fire_s, delay, r.first_pose_correct ? "yes" : "NO",
                r.initializations, r.false_initializations, 100 * r.tracked_fraction, 100 * r.rms_position_m,
                r.rms_orientation_deg, 100 * r.rms_position_ratio, r.tracker_cpu_s, r.simulator_cpu_s);
    false_inits += r.false_initializations;
    consistency.add(r.consistency);
    consistency_without_lag.add(r.consistency_without_lag);
    if (r.consistency.samples > 0)
    {
      ++covariance_scenes;
      undercovered += r.consistency.position3() < kCoveredEnough ? 1 : 0;
      undercovered_without_lag += r.consistency_without_lag.position3() < kCoveredEnough ? 1 : 0;
    }
    if (only >= 0)
    {
      std::printf("\nvision-only covariance: position inside 1 / 3 sigma %.1f / %.1f %%, rotation %.1f / %.1f %% "
                  "(without the lag term %.1f / %.1f %%, %.1f / %.1f %%; %llu samples)\n",
                  100 * r.consistency.position1(), 100 * r.consistency.position3(), 100 * r.consistency.rotation1(),
                  100 * r.consistency.rotation3(), 100 * r.consistency_without_lag.position1(),
                  100 * r.consistency_without_lag.position3(), 100 * r.consistency_without_lag.rotation1(),
                  100 * r.consistency_without_lag.rotation3(), (unsigned long long)r.consistency.samples);
      const auto& st = r.init_stats;
      std::printf("\nlosses %d, last loss: %s\n", r.losses, r.last_loss_reason.c_str());
      std::printf("\ninitialiser: attempts %llu, segments %llu, polygons %llu, cut by border %llu, pose failed %llu, "
                  "coverage failed %llu, unexplained %llu, too oblique %llu, ambiguous %llu, unconfirmed %llu, declined %llu, "
                  "accepted %llu\n\n",
                  (unsigned long long)st.attempts, (unsigned long long)st.segments, (unsigned long long)st.polygons,
                  (unsigned long long)st.cut_by_border, (unsigned long long)st.pose_failed,
                  (unsigned long long)st.coverage_failed, (unsigned long long)st.unexplained, (unsigned long long)st.too_oblique,
                  (unsigned long long)st.ambiguous, (unsigned long long)st.unconfirmed,
                  (unsigned long long)st.declined, (unsigned long long)st.accepted);
    }
    held += r.partial_views_held;
    resumed += r.partial_views_resumed;
    held_s += r.partial_view_held_s;
    held_scenes += r.partial_views_held > 0 ? 1 : 0;
    if (r.first_pose_s >= 0)
    {
      ++initialized;
      correct += r.first_pose_correct ? 1 : 0;
      delays.push_back(std::max(0.0, r.first_pose_delay_s));
      worst_delay = std::max(worst_delay, r.first_pose_delay_s);
      worst_tracked = std::min(worst_tracked, r.tracked_fraction);
      worst_rms_ratio = std::max(worst_rms_ratio, r.rms_position_ratio);
    }
    else
      worst_tracked = 0;
  }
  const int n = static_cast<int>(todo.size()) - failed;
  std::printf("\n**Summary** (%d scenes): initialised %d / %d, first pose correct (5 %% / 3 deg) %d / %d, "
              "false initialisations %d; first pose after the edges fire: median %.3f s, worst %.3f s; "
              "worst tracked fraction (>= 3 edges in view) %.1f %%; worst RMS %.2f %% of the distance%s\n",
              n, initialized, n, correct, n, false_inits, median(delays, -1), worst_delay, 100 * worst_tracked,
              100 * worst_rms_ratio, failed ? " (some scenes could not be built: see the rows)" : "");
  std::printf("\n**Vision-only covariance** (every 1 ms of tracking, %llu samples; a consistent estimate: 68.3 / 99.7 %%): "
              "position errors inside 1 / 3 sigma %.1f / %.1f %%, rotation %.1f / %.1f %%; scenes with fewer than %.0f %% "
              "of the position errors inside 3 sigma: %d of %d. Without the lag term (the Gauss-Newton covariance x %.0f "
              "alone): %.1f / %.1f %%, %.1f / %.1f %%, %d scenes\n",
              (unsigned long long)consistency.samples, 100 * consistency.position1(), 100 * consistency.position3(),
              100 * consistency.rotation1(), 100 * consistency.rotation3(), 100 * kCoveredEnough, undercovered,
              covariance_scenes, kVisionOnlyCovarianceScale, 100 * consistency_without_lag.position1(),
              100 * consistency_without_lag.position3(), 100 * consistency_without_lag.rotation1(),
              100 * consistency_without_lag.rotation3(), undercovered_without_lag);
  std::printf("\n**Partial views held** (a corner only in view, `partial_view_grace_s`): %llu in %d scenes, %llu of "
              "them resumed with a third side back (the rest ended in a loss), %.3f s held in all\n",
              (unsigned long long)held, held_scenes, (unsigned long long)resumed, held_s);
  return 0;
}
