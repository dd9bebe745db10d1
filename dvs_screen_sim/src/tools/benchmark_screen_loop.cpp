// benchmark_screen_loop: accuracy of the misalignment correction in the emulated screen in the
// loop (thesis ch. 3.4.1). For each run (seed) and each DVS pose: alignment from the blinking
// circle grid, then the blinking line grid through the corrected pipeline; prints the H_D
// residual, the mean line offset, the mean per-event distance and the pure-software floor of
// the latter, and the medians over all runs.
//   benchmark_screen_loop [--runs N]
// With --tracker (see screen_loop_tracker_comparison.cpp): the tracker on the emulated
// screen-in-the-loop flight vs its pure-software run.
//   benchmark_screen_loop --tracker [--seeds N] [--time-scales S,..] [--noise P,..] [--response-ms MS]
#include "screen_loop_tracker_comparison.h"

#include <dvs_screen_sim/screen_loop/emulated_screen_loop.h>
#include <dvs_screen_sim/screen_loop/line_grid_check.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace dvs_screen_sim;
using namespace dvs_screen_sim::screen_loop;

namespace
{
double median(std::vector<double> v)
{
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
}  // namespace

int main(int argc, char** argv)
{
  if (argc > 1 && std::strcmp(argv[1], "--tracker") == 0)
    return runScreenLoopTrackerComparison(argc - 1, argv + 1);
  int runs = 5;
  for (int i = 1; i < argc; ++i)
  {
    if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
      runs = std::atoi(argv[++i]);
    else
    {
      std::fprintf(stderr, "usage: benchmark_screen_loop [--runs N]\n"
                           "       benchmark_screen_loop --tracker --help\n");
      return 2;
    }
  }
  if (runs < 1)
  {
    std::fprintf(stderr, "benchmark_screen_loop: --runs must be >= 1\n");
    return 2;
  }
  if (!reexecUnderXvfbIfNoDisplay(argc, argv))
    return 1;
  WindowConfig wc;
  wc.fullscreen = false;
  wc.width = 1024;
  wc.height = 768;
  wc.vsync = false;
  GlScreenRenderer gl(wc);
  struct PoseCase
  {
    Eigen::Vector3d ypr;
    Eigen::Vector2d aim;
  };
  const std::vector<PoseCase> poses = {{{15, -12, 4}, {0.015, -0.01}}, {{-20, 8, -6}, {-0.02, 0.015}},
                                       {{10, 15, 0}, {0.0, 0.02}}};
  const Pose T_world_virtual = Pose::fromWorldCamera(orientationFromYawPitchRollDeg({4, -3, 8}), Eigen::Vector3d(0.03, -0.02, 1.0));
  const auto lines = lineGrid(7, 7, 0.12);
  const double width = 0.003;
  std::vector<double> residual, offset, distance, floor_distance, uncorrected_offset;
  int failures = 0;
  std::printf("run pose(ypr deg)        H_D_rms_px line_offset_px event_distance_px software_floor_px\n");
  for (int run = 0; run < runs; ++run)
    for (const auto& pc : poses)
    {
      EmulationConfig ec;
      ec.camera = dvs_calibration::CameraModel::dvs128();
      ec.T_wall_dvs = EmulationConfig::dvsPoseAimedAt(pc.ypr, pc.aim, 0.22);
      ec.monitor.pixel_pitch = 0.0006;
      ec.monitor.top_left = {-0.5 * 1024 * ec.monitor.pixel_pitch, 0.5 * 768 * ec.monitor.pixel_pitch};
      ec.monitor.black_level = 0.02;
      ec.monitor.white_level = 0.9;
      ec.pattern.spacing_vp = {0.085, 0.11};
      ec.pattern.radius_px = 11;
      ec.model.noise = noisePreset("realistic");
      ec.seed = static_cast<uint64_t>(run + 1);
      EmulatedScreenLoop loop(ec, gl);
      const GridAlignment a = loop.align();
      if (!a.ok)
      {
        std::printf("%3d %5.0f %5.0f %5.0f  alignment failed: %s\n", run, pc.ypr.x(), pc.ypr.y(), pc.ypr.z(),
                    a.reason.c_str());
        ++failures;
        continue;
      }
      const auto expected = expectedImageLines(ec.camera, T_world_virtual, lines);
      const auto st = eventLineDistances(loop.showLines(T_world_virtual, lines, width, true, 7), ec.camera, expected);
      const auto ref = referenceLineGridDistances(ec, T_world_virtual, 7, 7, 0.12, width, 7);
      residual.push_back(a.result.residual_dvs_px.rms);
      offset.push_back(st.mean_line_offset);
      distance.push_back(st.mean_event_distance);
      floor_distance.push_back(ref.mean_event_distance);
      std::printf("%3d %5.0f %5.0f %5.0f      %10.3f %14.3f %17.3f %17.3f\n", run, pc.ypr.x(), pc.ypr.y(), pc.ypr.z(),
                  a.result.residual_dvs_px.rms, st.mean_line_offset, st.mean_event_distance, ref.mean_event_distance);
    }
  std::printf("median over %zu alignments (%d failed): H_D residual %.3f px rms, line offset %.3f px, mean event "
              "distance %.3f px (pure-software floor %.3f px)\n",
              residual.size(), failures, median(residual), median(offset), median(distance), median(floor_distance));
  return failures == 0 ? 0 : 1;
}
