// benchmark_accuracy: the tracker's accuracy on the classes of issue 15 (range, 2000 deg/s,
// heavy noise, a far DAVIS346, two polygons, low contrast, the 2 m flip), each simulated by the
// suite's software DVS with seeds 1-5, scored against ground truth from the first pose on.
// Prints one row per class and seed and a summary per class (median and worst over the seeds).
//
//   rosrun dvs_line_tracker benchmark_accuracy [--seeds 1-5] [--class KEY[,KEY...]] [--jobs 2]
//                                              [--params tracker.yaml] [--out DIR] [--imu]
// --imu: the simulator's IMU fused (the tracker's ImuPropagator, imu_* parameters from --params).
#include "accuracy_classes.h"
#include "benchmark_tool.h"
#include "benchmark_stats.h"

#include <dvs_calibration/trajectory_file.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

using namespace dvs_line_tracker;

namespace
{
constexpr double kDeg = 180.0 / M_PI;

void usage()
{
  std::string keys;
  for (const auto& c : accuracyClasses())
    keys += (keys.empty() ? "" : ", ") + c.key;
  std::fprintf(stderr,
               "usage: benchmark_accuracy [--seeds A-B (default 1-5)] [--class KEY[,KEY...] (default: all)]\n"
               "       [--jobs J (1-16, default 2)] [--params tracker.yaml (as track_offline --params)]\n"
               "       [--out DIR (write each run's estimate and ground truth, TUM format)]\n"
               "       [--imu (fuse the simulated IMU: the tracker's ImuPropagator with the imu_* parameters)]\n"
               "classes: %s\n",
               keys.c_str());
}

struct Job
{
  const AccuracyClass* cls;
  int seed;
  AccuracyRun run;
  std::string error;
};
}  // namespace

int main(int argc, char** argv)
{
  int seed_from = 1, seed_to = 5, jobs = 2;
  std::vector<const AccuracyClass*> classes;
  std::string out_dir;
  bool use_imu = false;
  LineTrackerParams params;
  for (int i = 1; i < argc; ++i)
  {
    bool ok = i + 1 < argc;
    const std::string arg = argv[i];
    try
    {
      if (ok && arg == "--seeds")
      {
        const std::string v = argv[++i];
        const size_t dash = v.find('-');
        ok = dash == std::string::npos ? parseIntInRange(v, 0, 1000000, seed_from) && parseIntInRange(v, 0, 1000000, seed_to)
                                       : parseIntInRange(v.substr(0, dash), 0, 1000000, seed_from) &&
                                             parseIntInRange(v.substr(dash + 1), 0, 1000000, seed_to) && seed_to >= seed_from;
      }
      else if (ok && arg == "--class")
      {
        std::stringstream list(argv[++i]);
        for (std::string key; std::getline(list, key, ',');)
          classes.push_back(&accuracyClass(key));
      }
      else if (ok && arg == "--jobs")
        ok = parseIntInRange(argv[++i], 1, 16, jobs);
      else if (ok && arg == "--params")
        loadTrackerParamsYaml(argv[++i], params);
      else if (ok && arg == "--out")
        out_dir = argv[++i];
      else if (arg == "--imu")
        ok = use_imu = true;
      else
        ok = false;
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "benchmark_accuracy: %s\n", e.what());
      return 2;
    }
    if (!ok)
    {
      usage();
      return 2;
    }
  }
  if (classes.empty())
    for (const auto& c : accuracyClasses())
      classes.push_back(&c);
  if (!out_dir.empty() && !createOutputFolder("benchmark_accuracy", "--out", out_dir))
    return 1;

  std::vector<Job> work;
  for (const auto* c : classes)
    for (int seed = seed_from; seed <= seed_to; ++seed)
      work.push_back({c, seed, {}, {}});
  runJobs(work.size(), jobs, [&](size_t k) {
    Job& j = work[k];
    try
    {
      const AccuracyScene scene = simulateAccuracyScene(*j.cls, static_cast<uint64_t>(j.seed));
      dvs_calibration::Trajectory estimates;
      j.run = runAccuracyScene(scene, params, &estimates, use_imu);
      if (!out_dir.empty())
      {
        const std::string stem = out_dir + "/" + j.cls->key + "_seed" + std::to_string(j.seed);
        dvs_calibration::writeTumTrajectory(stem + ".txt", estimates);
        dvs_calibration::writeTumTrajectory(stem + "_groundtruth.txt", scene.ground_truth);
      }
    }
    catch (const std::exception& e)
    {
      j.error = e.what();
    }
    std::fprintf(stderr, "%s seed %d done\n", j.cls->key.c_str(), j.seed);
  });

  std::printf("## Accuracy per class and seed%s\n\n| class | seed | events | first pose [s] | RMS [cm / deg] | "
              "max [cm / deg] | tracked | losses | tracker M events/s (CPU) |%s\n|---|---|---|---|---|---|---|---|---|%s\n",
              use_imu ? ", the simulated IMU fused" : "", use_imu ? " IMU at the end |" : "", use_imu ? "---|" : "");
  for (const auto& j : work)
  {
    if (!j.error.empty())
    {
      std::printf("| %s | %d | error: %s |\n", j.cls->key.c_str(), j.seed, j.error.c_str());
      continue;
    }
    const auto& a = j.run.accuracy;
    std::printf("| %s | %d | %llu | %.3f | %.2f / %.2f | %.1f / %.1f | %.1f %% | %llu | %.2f |%s%s\n", j.cls->key.c_str(),
                j.seed, static_cast<unsigned long long>(j.run.events), a.first_estimate_s, 100 * a.rms_position_m,
                a.rms_orientation_rad * kDeg, 100 * a.max_position_m, a.max_orientation_rad * kDeg,
                100 * a.trackedFraction(), static_cast<unsigned long long>(j.run.stats.losses),
                j.run.events / std::max(1e-9, j.run.tracker_cpu_s) / 1e6, use_imu ? " " : "",
                use_imu ? (j.run.imu_status + " |").c_str() : "");
  }
  std::printf("\n## Summary (seeds %d-%d: median, worst in brackets%s)\n\n| class | RMS position [cm] | RMS orientation "
              "[deg] | max position [cm] | tracked | M events/s | issue: before | issue: target |\n"
              "|---|---|---|---|---|---|---|---|\n",
              seed_from, seed_to, use_imu ? "; the simulated IMU fused" : "");
  int failed = 0;
  for (const auto* c : classes)
  {
    std::vector<double> rp, ro, mp, tr, speed;
    for (const auto& j : work)
    {
      if (j.cls != c)
        continue;
      if (!j.error.empty())
      {
        ++failed;
        continue;
      }
      const auto& a = j.run.accuracy;
      // A run without any pose counts as the worst possible: untracked, infinite error.
      const bool any = a.first_estimate_s >= 0;
      rp.push_back(any ? 100 * a.rms_position_m : INFINITY);
      ro.push_back(any ? a.rms_orientation_rad * kDeg : INFINITY);
      mp.push_back(any ? 100 * a.max_position_m : INFINITY);
      tr.push_back(100 * a.trackedFraction());
      speed.push_back(j.run.events / std::max(1e-9, j.run.tracker_cpu_s) / 1e6);
    }
    std::printf("| %s: %s | %.2f (%.2f) | %.2f (%.2f) | %.1f (%.1f) | %.1f %% (%.1f %%) | %.2f | %s | %s |\n",
                c->key.c_str(), c->name.c_str(), median(rp), maxOf(rp), median(ro), maxOf(ro), median(mp),
                maxOf(mp), median(tr), minOf(tr), median(speed), c->before.c_str(), c->target.c_str());
  }
  if (failed)
    std::printf("\n%d runs failed (see the rows)\n", failed);
  return failed ? 1 : 0;
}
