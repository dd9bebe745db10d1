// benchmark_speed: how fast the tracker processes events on one core (issue 16, part 4): events
// per thread-CPU second for the whole run, the initialisation (events before the first pose) and
// the tracking (after it); the real-time factor; the per-event processing latency percentiles;
// the peak memory of the tracking; the accuracy beside it (so that a faster setting that is
// less accurate shows). Medians over --runs runs of each sequence. --imu fuses the simulated IMU
// (as a DAVIS's own IMU with ~use_imu: every event solved, the filter updated every 1 ms).
//
//   rosrun dvs_line_tracker benchmark_speed [--runs 5] [--params tracker.yaml] [--quick] [--imu]
#include "accuracy_classes.h"
#include "benchmark_tool.h"
#include "benchmark_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <malloc.h>
#include <string>
#include <vector>

using namespace dvs_line_tracker;

namespace
{
// The sequences: the DVS128 flip of the tracker's headline, and the DAVIS346 sequence of issue 16
// (two rolls at 1000 deg/s at 2 m, 2.6 s, ~0.7 M events/s on average with peaks several times that).
std::vector<AccuracyClass> speedSequences(bool quick)
{
  std::vector<AccuracyClass> s = {
      {"dvs128flip", "DVS128, 1200 deg/s flip at 2 m", "flip", "", "", ""},
      {"davis346rolls", "DAVIS346, two 1000 deg/s rolls at 2 m, 2.6 s", "flip",
       "camera: {preset: davis346}\nduration: 2.6\ntrajectory: {flip: {distance: 2.0, flips: 2, peak_rate_deg_s: 1000, "
       "first_flip_time: 0.75, flip_interval: 1.2}}\n",
       "", ""},
  };
  if (quick)
    s.pop_back();
  return s;
}

/// A /proc/self/status field in kB (-1 if unreadable).
long procStatusKb(const char* field)
{
  std::ifstream in("/proc/self/status");
  std::string line;
  const size_t n = std::strlen(field);
  while (std::getline(in, line))
    if (line.compare(0, n, field) == 0 && line.size() > n && line[n] == ':')
      return std::atol(line.c_str() + n + 1);
  return -1;
}

/// Heap bytes in use (glibc: small blocks plus mmapped large ones).
double heapBytes()
{
  const struct mallinfo2 m = mallinfo2();
  return static_cast<double>(m.uordblks) + static_cast<double>(m.hblkhd);
}

struct SpeedRun
{
  double whole_eps = 0, init_eps = 0, tracking_eps = 0, real_time_factor = 0;
  double heap_peak_mb = 0;  ///< the tracker's heap at its largest (sampled every 64 Ki events and at the end) [MB]
  dvs_calibration::AccuracyReport accuracy;
};

/// One run: thread CPU time of the event loop; the pose in force at each ground-truth sample
/// kept for the accuracy (not every pose: a per-event trajectory would dominate the memory).
SpeedRun runOnce(const AccuracyScene& s, const LineTrackerParams& params, bool use_imu)
{
  const auto& events = s.output.events;
  const auto& gt = s.ground_truth;
  dvs_calibration::Trajectory estimates;
  estimates.reserve(gt.size() + 1);
  const double heap0 = heapBytes();
  double heap_peak = heap0;
  SpeedRun r;
  double cpu = 0, cpu_init = 0;
  size_t init_events = events.size();
  {
    LineTracker tracker(s.config.camera, s.map, params);
    ImuFeed imu(tracker, params, use_imu ? &s.output.imu : nullptr);
    size_t next_gt = 0;
    bool have = false;
    dvs_calibration::StampedPose last;
    // The clock is read around the loop and once at the first pose (a thread-CPU clock read is
    // a system call, too slow to take per event); the loop's own bookkeeping is a comparison.
    const double c0 = threadCpuSeconds();
    for (size_t i = 0; i < events.size(); ++i)
    {
      const double t = events[i].t_ns * 1e-9;
      while (next_gt < gt.size() && gt[next_gt].t < t)
      {
        if (have && (estimates.empty() || estimates.back().t != last.t))
          estimates.push_back(last);
        ++next_gt;
      }
      if ((i & 0xffff) == 0xffff)
        heap_peak = std::max(heap_peak, heapBytes());
      imu.before(events[i].t_ns);
      if (tracker.processEvent(events[i]))
      {
        if (!have)
        {
          init_events = i + 1;
          cpu_init = threadCpuSeconds() - c0;
        }
        last = {t, tracker.pose()};
        have = true;
      }
    }
    cpu = threadCpuSeconds() - c0;
    if (have)
      estimates.push_back(last);
    heap_peak = std::max(heap_peak, heapBytes());
    // heap0 was taken after the estimates (one per ground-truth sample) were reserved: the
    // difference is the tracker's alone.
    r.heap_peak_mb = (heap_peak - heap0) / 1048576.0;
  }
  const double duration = events.empty() ? 0 : (events.back().t_ns - events.front().t_ns) * 1e-9;
  r.whole_eps = events.size() / std::max(1e-9, cpu);
  r.init_eps = init_events / std::max(1e-9, cpu_init);
  r.tracking_eps = (events.size() - std::min(init_events, events.size())) / std::max(1e-9, cpu - cpu_init);
  r.real_time_factor = duration / std::max(1e-9, cpu);
  r.accuracy = dvs_calibration::evaluateTrajectory(estimates, gt, 0.05);
  return r;
}

}  // namespace

int main(int argc, char** argv)
{
  int runs = 5;
  bool quick = false, use_imu = false;
  LineTrackerParams params;
  for (int i = 1; i < argc; ++i)
  {
    const bool has_value = i + 1 < argc;
    if (has_value && !std::strcmp(argv[i], "--runs"))
    {
      if (!parseIntInRange(argv[++i], 1, 1000, runs))
      {
        std::fprintf(stderr, "benchmark_speed: --runs must be 1-1000 (got '%s')\n", argv[i]);
        return 2;
      }
    }
    else if (has_value && !std::strcmp(argv[i], "--params"))
    {
      if (!loadParamsOption("benchmark_speed", argv[++i], params))
        return 2;
    }
    else if (!std::strcmp(argv[i], "--quick"))
      quick = true;
    else if (!std::strcmp(argv[i], "--imu"))
      use_imu = true;
    else
    {
      std::fprintf(stderr, "usage: benchmark_speed [--runs N (default 5)] [--params tracker.yaml] [--quick (DVS128 only)]\n"
                           "       [--imu (fuse the simulated IMU: the tracker's ImuPropagator with the imu_* parameters)]\n");
      return 2;
    }
  }
  std::printf("## Tracker speed on one core (thread CPU time of the event loop; median of %d runs, min-max in brackets%s)\n\n",
              runs, use_imu ? "; the simulated IMU fused" : "");
  std::printf("| sequence | events | length [s] | M events/s whole run | initialisation | tracking | real-time factor | "
              "latency p50 / p99 / p99.9 / max [us] | tracker heap peak / process peak RSS [MB] | RMS [cm / deg] | tracked |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& seq : speedSequences(quick))
  {
    AccuracyScene scene;
    try
    {
      scene = simulateAccuracyScene(seq, 1);
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "benchmark_speed: %s: %s\n", seq.key.c_str(), e.what());
      return 1;
    }
    std::vector<double> whole, init, tracking, rtf, mem;
    SpeedRun last;
    for (int k = 0; k < runs; ++k)
    {
      last = runOnce(scene, params, use_imu);
      whole.push_back(last.whole_eps / 1e6);
      init.push_back(last.init_eps / 1e6);
      tracking.push_back(last.tracking_eps / 1e6);
      rtf.push_back(last.real_time_factor);
      mem.push_back(last.heap_peak_mb);
    }
    std::vector<double> lat = poseUpdateLatencies(scene.config.camera, scene.map, params, scene.output.events,
                                                  use_imu ? &scene.output.imu : nullptr);
    const double p50 = percentile(lat, 0.5), p99 = percentile(lat, 0.99), p999 = percentile(lat, 0.999);
    const double pmax = maxOf(lat);
    auto range = [](const std::vector<double>& v) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.2f (%.2f-%.2f)", median(v), minOf(v), maxOf(v));
      return std::string(buf);
    };
    const auto& events = scene.output.events;
    const double length = events.empty() ? 0 : (events.back().t_ns - events.front().t_ns) * 1e-9;
    std::printf("| %s | %zu | %.2f | %s | %s | %s | %s | %.2f / %.2f / %.2f / %.0f | %.1f / %.0f | %.2f / %.2f | %.1f %% |\n",
                seq.name.c_str(), events.size(), length, range(whole).c_str(), range(init).c_str(),
                range(tracking).c_str(), range(rtf).c_str(), p50 * 1e6, p99 * 1e6, p999 * 1e6, pmax * 1e6, median(mem),
                procStatusKb("VmHWM") / 1024.0,
                100 * last.accuracy.rms_position_m, last.accuracy.rms_orientation_rad * 180 / M_PI,
                100 * last.accuracy.trackedFraction());
    std::fflush(stdout);
  }
  std::printf("\nTargets (issue 16): >= 5 M events/s on the whole run of both sequences, initialisation >= 2 M/s, "
              "real-time factor >= 3 on the DAVIS346 sequence, accuracy within 5 %% of today's.\n");
  return 0;
}
