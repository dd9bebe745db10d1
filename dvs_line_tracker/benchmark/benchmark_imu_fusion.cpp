// benchmark_imu_fusion: the line tracker with and without its IMU (issue 17) on the software
// DVS's 1200 deg/s flips (DVS128 with lens distortion, realistic noise, the MPU-6150-class IMU of
// dvs_screen_sim with random initial biases), at several distances and seeds, with and without a
// blackout of every event in the middle of the flip. Prints per run and as medians / worst:
//  - RMS position / orientation of the per-event poses, with and without IMU;
//  - with the blackout: the error right after it (the first pose after the gap), losses and
//    re-initialisations, RMS after the blackout;
//  - the IMU filter's covariance consistency: the fraction of 1 kHz samples whose error lies
//    inside the reported 1 and 3 sigma, per axis (position in the world, rotation in camera axes);
//    and the same for vision alone (the tracker's pose against the covariance ~odometry reports
//    without IMU).
//
//   rosrun dvs_line_tracker benchmark_imu_fusion [--seeds 1-5] [--distances 1.4,2.3] [--blackout 0.15]
//                                                [--floor] [--params tracker.yaml] [--trace FILE]
// --floor: the square on the floor (the simulator's gravity along world z instead of -y: the
// gravity the tracker estimates starts tilted, the camera accelerating sideways then).
// --trace writes per consistency sample of every run (imu_flip_evaluation.h): t, position error
// (3), its sigmas (3), rotation error (3, camera axes), its sigmas (3)
#include "benchmark_tool.h"
#include "benchmark_stats.h"
#include "imu_flip_evaluation.h"

#include <dvs_line_tracker/tracker_params.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

using namespace dvs_line_tracker;

namespace
{
constexpr double kDeg = 180.0 / M_PI;
std::FILE* g_trace = nullptr;  ///< --trace

/// The summary of the first poses after the blackout: median (worst) in cm / deg over the runs
/// tracking then, and how many were not (kNotTracking stands for those in the lists).
constexpr double kNotTracking = 1e9;
std::string afterBlackout(const std::vector<double>& position_m, const std::vector<double>& orientation_rad)
{
  std::vector<double> p, r;
  for (size_t i = 0; i < position_m.size(); ++i)
    if (position_m[i] < kNotTracking)
    {
      p.push_back(position_m[i]);
      r.push_back(orientation_rad[i]);
    }
  const size_t lost = position_m.size() - p.size();
  if (p.empty())
    return "not tracking in any run";
  char buf[160];
  std::snprintf(buf, sizeof(buf), "%.2f (%.2f) cm / %.2f (%.2f) deg", 100 * median(p), 100 * maxOf(p),
                median(r) * kDeg, maxOf(r) * kDeg);
  return lost ? std::string(buf) + ", not tracking in " + std::to_string(lost) + " of " +
                    std::to_string(position_m.size()) + " runs"
              : std::string(buf);
}

FlipRunResult run(const FlipScene& s, const LineTrackerParams& params, bool use_imu, double blackout_start,
                  double blackout_s)
{
  FlipRunOptions o;
  o.params = params;
  o.use_imu = use_imu;
  o.blackout_from_s = blackout_start;
  o.blackout_s = blackout_s;
  o.trace = g_trace;
  return runFlip(s, o);
}

std::vector<double> parseList(const std::string& text)
{
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
    out.push_back(std::atof(item.c_str()));
  return out;
}
}  // namespace

int main(int argc, char** argv)
{
  int seed_from = 1, seed_to = 5;
  std::vector<double> distances = {1.4, 2.3};
  bool floor = false;
  double blackout = 0.15;
  LineTrackerParams params;
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc && std::sscanf(argv[i + 1], "%d-%d", &seed_from, &seed_to) >= 1)
    {
      if (!std::strchr(argv[i + 1], '-'))
        seed_to = seed_from;
      ++i;
    }
    else if (!std::strcmp(argv[i], "--distances") && i + 1 < argc)
      distances = parseList(argv[++i]);
    else if (!std::strcmp(argv[i], "--floor"))
      floor = true;
    else if (!std::strcmp(argv[i], "--blackout") && i + 1 < argc)
      blackout = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--trace") && i + 1 < argc)
    {
      g_trace = std::fopen(argv[++i], "w");
      if (!g_trace)
      {
        std::fprintf(stderr, "benchmark_imu_fusion: cannot write %s\n", argv[i]);
        return 2;
      }
    }
    else if (!std::strcmp(argv[i], "--params") && i + 1 < argc)
    {
      if (!loadParamsOption("benchmark_imu_fusion", argv[++i], params))
        return 2;
    }
    else
    {
      std::fprintf(stderr, "usage: benchmark_imu_fusion [--seeds A-B] [--distances D1,D2] [--blackout S] [--floor]\n"
                           "       [--params tracker.yaml] [--trace FILE]\n");
      return 2;
    }
  }
  if (seed_to < seed_from || distances.empty() || !(blackout > 0 && blackout < 0.6))
  {
    std::fprintf(stderr, "benchmark_imu_fusion: bad --seeds, --distances or --blackout (0 < S < 0.6)\n");
    return 2;
  }
  std::printf("1200 deg/s flips (DVS128, lens distortion, realistic noise, MPU-6150-class IMU with random biases), "
              "the square on %s;\nblackout: no events for %.0f ms centred on the flip (t 0.75 s)\n\n",
              floor ? "the floor (gravity along world z)" : "a wall (gravity along world -y)", blackout * 1e3);
  std::printf("| distance | seed | RMS without IMU (cm / deg) | RMS with IMU (cm / deg) | change | blackout without IMU: "
              "losses / reinit | blackout with IMU: losses / reinit / bridged | error after blackout (cm / deg) | "
              "RMS after blackout (cm) | inside 1 / 3 sigma: position | rotation | vision alone: position | rotation | "
              "IMU at the end |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (double d : distances)
  {
    std::vector<double> rms_vis, rms_imu, change, end_p, end_r, in1, in3, in1r, in3r, vin1, vin3, vin1r, vin3r;
    uint64_t imu_losses = 0, vis_losses = 0;
    for (int seed = seed_from; seed <= seed_to; ++seed)
    {
      std::ostringstream overrides;
      overrides << "trajectory: {flip: {distance: " << d << "}}";
      if (floor)
        overrides << "\nimu: {gravity: [0.0, 0.0, 9.81]}";
      const FlipScene s = simulateFlip(overrides.str(), static_cast<uint64_t>(seed));
      const FlipRunResult v = run(s, params, false, 0, 0);
      const FlipRunResult m = run(s, params, true, 0, 0);
      const double start = 0.75 - blackout / 2;
      const FlipRunResult vb = run(s, params, false, start, blackout);
      const FlipRunResult mb = run(s, params, true, start, blackout);
      const double ch = m.all.rms_position_m / std::max(1e-9, v.all.rms_position_m) - 1.0;
      rms_vis.push_back(v.all.rms_position_m);
      rms_imu.push_back(m.all.rms_position_m);
      change.push_back(ch);
      end_p.push_back(mb.after_gap_position_m < 0 ? kNotTracking : mb.after_gap_position_m);
      end_r.push_back(mb.after_gap_orientation_rad < 0 ? kNotTracking : mb.after_gap_orientation_rad);
      in1.push_back(m.consistency.position1());
      in3.push_back(m.consistency.position3());
      in1r.push_back(m.consistency.rotation1());
      in3r.push_back(m.consistency.rotation3());
      vin1.push_back(v.consistency.position1());
      vin3.push_back(v.consistency.position3());
      vin1r.push_back(v.consistency.rotation1());
      vin3r.push_back(v.consistency.rotation3());
      imu_losses += mb.stats.losses + m.stats.losses;
      vis_losses += vb.stats.losses;
      std::printf("| %.1f m | %d | %.2f / %.2f | %.2f / %.2f | %+.0f %% | %llu / %llu | %llu / %llu / %llu | %s | %.2f | "
                  "%.0f / %.1f %% | %.0f / %.1f %% | %.0f / %.1f %% | %.0f / %.1f %% | %s |\n",
                  d, seed, 100 * v.all.rms_position_m, v.all.rms_orientation_rad * kDeg, 100 * m.all.rms_position_m,
                  m.all.rms_orientation_rad * kDeg, 100 * ch, static_cast<unsigned long long>(vb.stats.losses),
                  static_cast<unsigned long long>(vb.stats.reinitializations),
                  static_cast<unsigned long long>(mb.stats.losses),
                  static_cast<unsigned long long>(mb.stats.reinitializations),
                  static_cast<unsigned long long>(mb.stats.gaps_bridged),
                  mb.after_gap_position_m < 0 ? "not tracking"
                                        : (std::to_string(100 * mb.after_gap_position_m).substr(0, 4) + " / " +
                                           std::to_string(mb.after_gap_orientation_rad * kDeg).substr(0, 4))
                                              .c_str(),
                  100 * mb.after.rms_position_m, 100 * in1.back(), 100 * in3.back(), 100 * in1r.back(),
                  100 * in3r.back(), 100 * vin1.back(), 100 * vin3.back(), 100 * vin1r.back(), 100 * vin3r.back(),
                  toString(m.imu_status));
      std::fflush(stdout);
    }
    std::printf("| **%.1f m: median (worst)** | | %.2f (%.2f) | %.2f (%.2f) | %+.0f %% (%+.0f %%) | %llu losses in all | "
                "%llu losses in all | %s | | %.0f / %.1f %% | %.0f / %.1f %% | %.0f / %.1f %% | "
                "%.0f / %.1f %% | |\n",
                d, 100 * median(rms_vis), 100 * maxOf(rms_vis), 100 * median(rms_imu), 100 * maxOf(rms_imu),
                100 * median(change), 100 * maxOf(change), static_cast<unsigned long long>(vis_losses),
                static_cast<unsigned long long>(imu_losses), afterBlackout(end_p, end_r).c_str(), 100 * median(in1), 100 * median(in3), 100 * median(in1r),
                100 * median(in3r), 100 * median(vin1), 100 * median(vin3), 100 * median(vin1r), 100 * median(vin3r));
  }
  return 0;
}
