// Benchmark: accuracy and time to calibrate on emulated recordings (and, with --sim, on
// recordings of the suite's software DVS, dvs_screen_sim, run as an external program).
//   benchmark_calibration [--runs N] [--poses P] [--sim [--keep]]
// (--keep leaves the simulated recordings in /tmp/dvs_calibration_benchmark_SEED/sim.)
// Prints one line per run and the medians per scenario.
#include "emulated_screen.h"
#include "sim_scenario.h"

#include <dvs_calibration/calibration_session.h>
#include <dvs_driver/event_text_io.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <sys/stat.h>
#include <vector>

using namespace dvs_calibration;
using namespace dvs_calibration::testing;

namespace
{
struct Run
{
  double fx_err_pct = 0, fy_err_pct = 0, cx_err = 0, cy_err = 0, k1_err = 0, rms = 0;
  double views = 0, process_s = 0, calibrate_s = 0, events_m = 0, sim_s = 0;
  bool ok = false;
};

double median(std::vector<double> v)
{
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Run calibrateEvents(const dvs_driver::EventVector& events, const CameraModel& truth, double spacing, DetectorKind kind)
{
  using clock = std::chrono::steady_clock;
  Run r;
  SessionConfig cfg;
  cfg.detector = kind;
  cfg.calibrator.spacing_m = spacing;
  CalibrationSession session(cfg);
  const auto t0 = clock::now();
  session.addEvents(events);
  session.flush();
  const auto t1 = clock::now();
  r.events_m = events.size() * 1e-6;
  r.process_s = std::chrono::duration<double>(t1 - t0).count();
  r.views = static_cast<double>(session.views().size());
  try
  {
    const CalibrationResult res = session.calibrate();
    r.calibrate_s = std::chrono::duration<double>(clock::now() - t1).count();
    const CameraIntrinsics& e = res.camera.intrinsics();
    const CameraIntrinsics& t = truth.intrinsics();
    r.fx_err_pct = 100.0 * std::abs(e.fx - t.fx) / t.fx;
    r.fy_err_pct = 100.0 * std::abs(e.fy - t.fy) / t.fy;
    r.cx_err = std::abs(e.cx - t.cx);
    r.cy_err = std::abs(e.cy - t.cy);
    r.k1_err = std::abs(e.k1 - t.k1);
    r.rms = res.rms_px;
    r.ok = true;
  }
  catch (const std::exception& ex)
  {
    std::fprintf(stderr, "calibration failed: %s\n", ex.what());
  }
  return r;
}

void print(const char* name, const Run& r)
{
  std::printf("%-28s %s views %3.0f  |dfx| %5.2f%%  |dfy| %5.2f%%  |dcx| %4.2f px  |dcy| %4.2f px  |dk1| %.4f  RMS %.3f px  "
              "%5.2f Mev  process %6.3f s (%5.1f Mev/s)  calibrate %6.3f s%s\n",
              name, r.ok ? "ok  " : "FAIL", r.views, r.fx_err_pct, r.fy_err_pct, r.cx_err, r.cy_err, r.k1_err, r.rms,
              r.events_m, r.process_s, r.events_m / std::max(1e-9, r.process_s), r.calibrate_s,
              r.sim_s > 0 ? ("  (simulation " + std::to_string(r.sim_s).substr(0, 5) + " s)").c_str() : "");
  std::fflush(stdout);
}

void printMedian(const char* name, const std::vector<Run>& runs)
{
  auto col = [&](double Run::*m) {
    std::vector<double> v;
    for (const Run& r : runs)
      v.push_back(r.*m);
    return median(v);
  };
  int ok = 0;
  for (const Run& r : runs)
    ok += r.ok;
  std::printf("MEDIAN %-21s %d/%zu ok, views %.0f, |dfx| %.2f%%, |dfy| %.2f%%, |dcx| %.2f px, |dcy| %.2f px, |dk1| %.4f, "
              "RMS %.3f px, process %.3f s for %.2f Mev, calibrate %.3f s\n",
              name, ok, runs.size(), col(&Run::views), col(&Run::fx_err_pct), col(&Run::fy_err_pct), col(&Run::cx_err),
              col(&Run::cy_err), col(&Run::k1_err), col(&Run::rms), col(&Run::process_s), col(&Run::events_m),
              col(&Run::calibrate_s));
}
}  // namespace

int main(int argc, char** argv)
{
  int runs = 5, n_poses = 24;
  bool sim = false, keep = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc)
      runs = std::atoi(argv[++i]);
    else if (a == "--poses" && i + 1 < argc)
      n_poses = std::atoi(argv[++i]);
    else if (a == "--sim")
      sim = true;
    else if (a == "--keep")
      keep = true;
    else
    {
      std::fprintf(stderr, "usage: benchmark_calibration [--runs N] [--poses P] [--sim [--keep]]\n");
      return 2;
    }
  }
  if (runs < 1 || n_poses < 5)
  {
    std::fprintf(stderr, "benchmark_calibration: --runs >= 1 and --poses >= 5\n");
    return 2;
  }
  std::printf("dvs_calibration benchmark: DVS128 (fx=fy=115, cx=cy=63.5, k1=-0.12, k2=0.03), 7x7 grid, "
              "%d poses tilted up to 45 deg, %d runs per scenario\n",
              n_poses, runs);

  struct Scenario
  {
    const char* name;
    bool flicker;
    DetectorKind kind;
  };
  const Scenario scenarios[] = {{"emulated flicker/counts", true, DetectorKind::Counts},
                                {"emulated blink/counts", false, DetectorKind::Counts},
                                {"emulated blink/blink", false, DetectorKind::Blink}};
  for (const Scenario& sc : scenarios)
  {
    std::vector<Run> all;
    for (int k = 0; k < runs; ++k)
    {
      EmulatedScreen screen;
      screen.backlight_flicker = sc.flicker;
      if (!sc.flicker)
      {
        screen.flicker_hz = 20;
        screen.events_per_log_step = 2.0;
      }
      const uint32_t seed = 1000 + static_cast<uint32_t>(k);
      const auto poses = calibrationPoses(screen, n_poses, 45.0, seed);
      const auto events = emulateRecording(screen, poses, 400000000, 100000000, seed);
      all.push_back(calibrateEvents(events, screen.camera, screen.spacing_m, sc.kind));
      print(sc.name, all.back());
    }
    printMedian(sc.name, all);
  }

  if (sim)
  {
    const std::string simulate = findSimulator(DVS_DEVEL_LIB_DIR);
    if (simulate.empty())
    {
      std::fprintf(stderr, "benchmark_calibration: dvs_screen_sim's simulate not found (set DVS_SCREEN_SIM_SIMULATE)\n");
      return 1;
    }
    const struct
    {
      const char* name;
      bool flicker;
      DetectorKind kind;
    } sims[] = {{"dvs_screen_sim flicker/counts", true, DetectorKind::Counts},
                {"dvs_screen_sim blink/blink", false, DetectorKind::Blink}};
    for (const auto& sc : sims)
    {
      std::vector<Run> all;
      for (int k = 0; k < runs; ++k)
      {
        SimScenario s;
        s.backlight_flicker = sc.flicker;
        if (!sc.flicker)
          s.flicker_hz = 20;
        const uint32_t seed = 2000 + static_cast<uint32_t>(k);
        const std::string dir = "/tmp/dvs_calibration_benchmark_" + std::to_string(seed);
        ::mkdir(dir.c_str(), 0755);
        const auto poses = orderForShortMoves(s.screen, calibrationPoses(s.screen, n_poses, 45.0, seed));
        const std::string cfg = writeSimScenario(dir, s, poses);
        const auto t0 = std::chrono::steady_clock::now();
        const std::string cmd = simulate + " --scenario file --out " + dir + "/sim --seed " + std::to_string(seed) +
                                " --config " + cfg + " > " + dir + "/simulate.log 2>&1";
        if (std::system(cmd.c_str()) != 0)
        {
          std::fprintf(stderr, "simulation failed: see %s/simulate.log\n", dir.c_str());
          return 1;
        }
        const double sim_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const auto events = dvs_driver::readEventsText(dir + "/sim/events.txt");
        all.push_back(calibrateEvents(events, s.screen.camera, s.screen.spacing_m, sc.kind));
        all.back().sim_s = sim_s;
        print(sc.name, all.back());
        if (!keep)
          std::system(("rm -rf '" + dir + "'").c_str());
      }
      printMedian(sc.name, all);
    }
  }
  return 0;
}
