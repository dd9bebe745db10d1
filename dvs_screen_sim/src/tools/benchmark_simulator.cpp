// benchmark_simulator: simulated events per second and real-time factor of the software DVS for
// the 1200 deg/s quadrotor flip, at 128x128 (DVS128) and 346x260 (DAVIS346), one core, plus the
// process's peak memory. Prints the median of `--runs` runs (default 5).
//   benchmark_simulator [--runs N] [--noise clean|realistic|noisy]
#include <dvs_screen_sim/dataset.h>

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

using namespace dvs_screen_sim;

namespace
{
double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv)
{
  int runs = 5;
  std::string noise = "realistic";
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--runs") && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--noise") && i + 1 < argc)
      noise = argv[++i];
    else
    {
      std::fprintf(stderr, "usage: benchmark_simulator [--runs N] [--noise clean|realistic|noisy]\n");
      return 2;
    }
  }
  std::printf("# dvs_screen_sim benchmark: flip at 1200 deg/s peak roll rate, noise preset %s, median of %d runs\n",
              noise.c_str(), runs);
  std::printf("%-10s %10s %12s %12s %14s %12s %10s\n", "camera", "sim_s", "events", "samples", "events/s(cpu)",
              "cpu_s", "x_realtime");
  for (const char* preset : {"dvs128", "davis346"})
  {
    YAML::Node over;
    over["camera"]["preset"] = preset;
    over["events"]["noise"]["preset"] = noise;
    SimConfig config;
    try
    {
      config = resolveSimConfig("flip", over, 1);
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "benchmark_simulator: %s\n", e.what());
      return 1;
    }
    std::vector<double> cpu;
    size_t events = 0;
    uint64_t samples = 0;
    for (int r = 0; r < runs; ++r)
    {
      const SimulationOutput out = runSimulation(config);
      cpu.push_back(out.cpu_seconds);
      events = out.events.size();
      samples = out.stats.samples;
    }
    const double c = median(cpu);
    std::printf("%-10s %10.3f %12zu %12llu %14.0f %12.4f %10.2f\n", preset, config.duration, events,
                static_cast<unsigned long long>(samples), events / c, c, config.duration / c);
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("peak resident memory: %.1f MB\n", usage.ru_maxrss / 1024.0);
  return 0;
}
