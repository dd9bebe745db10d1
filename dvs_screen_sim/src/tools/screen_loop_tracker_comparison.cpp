// benchmark_screen_loop --tracker: issue 7's last criterion, "the tracker, run on the emulated
// screen-in-the-loop flight, reaches accuracy within 1.5x of its pure-software run", by one
// command. For each noise preset and seed: the pure-software run (`simulate`), the emulated
// screen in the loop at each time scale (`emulate_screen_loop`, same scenario, seed and noise
// preset) and, for noisy presets, the pure-software run with the sensor as slow as the screen
// makes it (noise rates x S, refractory period and latency / S: the noise the slowed playback
// puts into each trajectory second). Each dataset is tracked by dvs_line_tracker's
// `track_offline` (run as an external program: the tracker build-depends on this package, so
// linking it here would make a dependency loop, as are `simulate` and `emulate_screen_loop`) and
// scored by the suite's one accuracy metric, dvs_calibration::evaluateTrajectory.
#include "screen_loop_tracker_comparison.h"

#include <dvs_calibration/trajectory_accuracy.h>
#include <dvs_calibration/trajectory_file.h>
#include <dvs_screen_sim/event_simulator.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;

namespace dvs_screen_sim
{
namespace
{
struct RunResult
{
  bool ok = false;
  std::string dir;
  size_t events = 0;
  double position_rms_mm = 0, orientation_rms_deg = 0;
  double coverage = 0;  ///< share of the flight's ground-truth samples tracked (evaluateTrajectory's rule)
  double first_estimate = 0;  ///< time of the first pose (when the tracker initialised)
};

double median(std::vector<double> v)
{
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

std::string quote(const std::string& s)
{
  std::string q = "'";
  for (char c : s)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs a shell command, returns its stdout (stderr goes to `log`); throws on a non-zero status.
std::string runCommand(const std::string& command, const std::string& log)
{
  const std::string full = command + " 2>>" + quote(log);
  FILE* pipe = popen(full.c_str(), "r");
  if (!pipe)
    throw std::runtime_error("cannot run: " + command);
  std::string out;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0)
    out.append(buf.data(), n);
  const int status = pclose(pipe);
  if (status != 0)
    throw std::runtime_error("failed (status " + std::to_string(status) + "): " + command + " (see " + log + ")");
  return out;
}

size_t countEventLines(const std::string& path)
{
  std::ifstream in(path);
  size_t n = 0;
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#')
      ++n;
  return n;
}

std::vector<double> parseList(const std::string& s)
{
  std::vector<double> v;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ','))
  {
    char* end = nullptr;
    const double d = std::strtod(tok.c_str(), &end);
    if (tok.empty() || *end != '\0' || !(d > 0))
      throw std::invalid_argument("bad number '" + tok + "' in list '" + s + "'");
    v.push_back(d);
  }
  return v;
}

std::vector<std::string> splitNames(const std::string& s)
{
  std::vector<std::string> v;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ','))
    if (!tok.empty())
      v.push_back(tok);
  return v;
}

std::string selfDirectory()
{
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : exe.parent_path().string();
}

struct Tools
{
  std::string simulate, emulate, track;
};

/// Scores dir/trajectory.txt against dir/groundtruth.txt from trajectory time `from` on with the
/// suite's one accuracy metric (ground-truth samples, the latest estimate at or before each).
void score(const std::string& dir, double from, RunResult& r)
{
  const auto estimate =
      dvs_calibration::readTumTrajectory(dir + "/trajectory.txt", dvs_calibration::TimeOrder::NonDecreasing);
  const auto groundtruth = dvs_calibration::readTumTrajectory(dir + "/groundtruth.txt");
  dvs_calibration::AccuracyOptions options;
  options.from_s = from;
  const dvs_calibration::AccuracyReport a = dvs_calibration::evaluateTrajectory(estimate, groundtruth, options);
  if (a.samples_fresh == 0)
    throw std::runtime_error("no estimated pose inside the ground truth's time span of " + dir);
  r.position_rms_mm = a.rms_position_m * 1e3;
  r.orientation_rms_deg = a.rms_orientation_rad * 180.0 / M_PI;
  // The share of the whole flight (from `from`) tracked: before the tracker initialises nothing is.
  size_t flight = 0;
  for (const auto& g : groundtruth)
    flight += g.t >= from ? 1 : 0;
  r.coverage = flight > 0 ? static_cast<double>(a.samples_tracked) / static_cast<double>(flight) : 0.0;
}

double firstEstimateTime(const std::string& path)
{
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#')
      return std::strtod(line.c_str(), nullptr);
  throw std::runtime_error("the tracker wrote no pose to " + path);
}

/// Tracks `dir` and scores it against its ground truth.
RunResult trackAndScore(const Tools& tools, const std::string& dir, const std::string& log)
{
  RunResult r;
  r.dir = dir;
  r.events = countEventLines(dir + "/events.txt");
  runCommand(quote(tools.track) + " --events " + quote(dir + "/events.txt") + " --calib " + quote(dir + "/calib.txt") +
                 " --map " + quote(dir + "/map.yaml") + " --out " + quote(dir + "/trajectory.txt") + " >/dev/null",
             log);
  r.first_estimate = firstEstimateTime(dir + "/trajectory.txt");
  score(dir, -1e9, r);
  r.ok = true;
  return r;
}

/// Position and orientation RMS ratios of `r` to `sw` over the span both track (from the later
/// initialisation on): accuracy while tracking, apart from when tracking starts.
std::pair<double, double> commonSpanRatios(const RunResult& r, const RunResult& sw)
{
  const double from = std::max(r.first_estimate, sw.first_estimate);
  RunResult a, b;
  score(r.dir, from, a);
  score(sw.dir, from, b);
  return {a.position_rms_mm / b.position_rms_mm, a.orientation_rms_deg / b.orientation_rms_deg};
}

std::string noiseYaml(const NoiseConfig& n)
{
  std::ostringstream o;
  o.precision(10);
  o << "events:\n  noise:\n    threshold_sigma: " << n.threshold_sigma << "\n    refractory_period: "
    << n.refractory_period << "\n    latency: " << n.latency << "\n    latency_jitter: " << n.latency_jitter
    << "\n    background_rate: " << n.background_rate << "\n    hot_pixel_fraction: " << n.hot_pixel_fraction
    << "\n    hot_pixel_rate: " << n.hot_pixel_rate
    << "\n    random_initial_reference: " << (n.random_initial_reference ? "true" : "false") << "\n";
  return o.str();
}

void usage(std::FILE* out)
{
  std::fprintf(out,
               "usage: benchmark_screen_loop --tracker [--seeds N] [--time-scales S1,S2,..] [--noise P1,P2,..]\n"
               "           [--response-ms MS] [--scenario NAME] [--work DIR] [--track-offline PATH]\n"
               "  --seeds N          seeds 0..N-1 per noise preset (default 3; a preset without random parts,\n"
               "                     clean, runs seed 0 only); medians over them\n"
               "  --time-scales      playback slow-down factors of the screen (default 10)\n"
               "  --noise            noise presets (default clean,realistic)\n"
               "  --response-ms MS   the virtual monitor's response time (default 5)\n"
               "  --scenario NAME    simulate's scenario (default flip)\n"
               "  --work DIR         where the datasets go (default /tmp/screen_loop_tracker_benchmark)\n"
               "  --track-offline    dvs_line_tracker's track_offline (default: next to this program's folder,\n"
               "                     ../dvs_line_tracker/track_offline)\n");
}
}  // namespace

int runScreenLoopTrackerComparison(int argc, char** argv)
{
  int seeds = 3;
  std::vector<double> time_scales = {10};
  std::vector<std::string> presets = {"clean", "realistic"};
  double response_ms = 5;
  std::string scenario = "flip", work = "/tmp/screen_loop_tracker_benchmark";
  const std::string here = selfDirectory();
  Tools tools{here + "/simulate", here + "/emulate_screen_loop", here + "/../dvs_line_tracker/track_offline"};
  try
  {
    for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      if (a == "-h" || a == "--help")
      {
        usage(stdout);
        return 0;
      }
      if (i + 1 >= argc)
        throw std::invalid_argument(a + " needs a value");
      const std::string v = argv[++i];
      if (a == "--seeds")
      {
        seeds = std::atoi(v.c_str());
        if (seeds < 1)
          throw std::invalid_argument("--seeds must be >= 1");
      }
      else if (a == "--time-scales")
        time_scales = parseList(v);
      else if (a == "--noise")
      {
        presets = splitNames(v);
        for (const auto& p : presets)
          noisePreset(p);  // throws naming the known presets
      }
      else if (a == "--response-ms")
      {
        char* end = nullptr;
        response_ms = std::strtod(v.c_str(), &end);
        if (v.empty() || *end != '\0' || !(response_ms >= 0))
          throw std::invalid_argument("--response-ms must be a number >= 0");
      }
      else if (a == "--scenario")
        scenario = v;
      else if (a == "--work")
        work = v;
      else if (a == "--track-offline")
        tools.track = v;
      else
        throw std::invalid_argument("unknown option " + a);
    }
    for (const auto* t : {&tools.simulate, &tools.emulate, &tools.track})
      if (access(t->c_str(), X_OK) != 0)
        throw std::runtime_error("program not found: " + *t + " (build dvs_line_tracker, or pass --track-offline)");
    fs::create_directories(work);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "benchmark_screen_loop --tracker: %s\n", e.what());
    usage(stderr);
    return 2;
  }
  const std::string log = work + "/log.txt";
  std::printf("tracker on the emulated screen in the loop vs pure software: scenario %s, monitor response %.1f ms, "
              "seeds 0..%d\n(datasets in %s, stderr of the programs in %s)\n",
              scenario.c_str(), response_ms, seeds - 1, work.c_str(), log.c_str());
  std::printf("pos/ori: RMS position [mm] / orientation [deg] error (dvs_calibration::evaluateTrajectory: at the\n"
              "ground-truth samples, the latest pose at or before each); tracked: share of the flight's ground-truth\n"
              "samples tracked (a pose at most 50 ms old within 10 cm / 10 deg), from init [s] on; ratios to the\n"
              "same seed's pure-software run over each run's own span, and over the span both track (common)\n");
  std::printf("%-10s %4s %-26s %8s %9s %9s %7s %6s %9s %9s %9s %9s\n", "noise", "seed", "run", "events", "pos_rms",
              "ori_rms", "tracked", "init", "pos_ratio", "ori_ratio", "pos_comm", "ori_comm");
  // Per (noise, run label): per-seed values and ratios to the same seed's pure-software run.
  struct Acc
  {
    std::vector<double> pos, ori, cov, pos_ratio, ori_ratio, events, common_pos_ratio, common_ori_ratio;
    int failed = 0;
    std::pair<double, double> last_common{0, 0};
  };
  std::map<std::string, std::map<std::string, Acc>> acc;
  std::vector<std::pair<std::string, std::string>> order;
  auto record = [&](const std::string& noise, const std::string& label, const RunResult& r, const RunResult& sw) {
    auto& a = acc[noise][label];
    if (a.pos.empty() && a.failed == 0)
      order.emplace_back(noise, label);
    if (!r.ok)
    {
      ++a.failed;
      return;
    }
    a.pos.push_back(r.position_rms_mm);
    a.ori.push_back(r.orientation_rms_deg);
    a.cov.push_back(r.coverage);
    a.events.push_back(static_cast<double>(r.events));
    const double pr = sw.ok ? r.position_rms_mm / sw.position_rms_mm : 0, orr = sw.ok ? r.orientation_rms_deg / sw.orientation_rms_deg : 0;
    if (sw.ok)
    {
      a.pos_ratio.push_back(pr);
      a.ori_ratio.push_back(orr);
      try
      {
        const auto c = commonSpanRatios(r, sw);
        a.common_pos_ratio.push_back(c.first);
        a.common_ori_ratio.push_back(c.second);
        a.last_common = c;
      }
      catch (const std::exception& e)
      {
        std::fprintf(stderr, "benchmark_screen_loop --tracker: %s\n", e.what());
        a.last_common = {0, 0};
      }
    }
  };
  auto report = [&](const std::string& noise, int seed, const std::string& label, const RunResult& r,
                    const RunResult& sw) {
    record(noise, label, r, sw);
    if (!r.ok)
    {
      std::printf("%-10s %4d %-26s failed\n", noise.c_str(), seed, label.c_str());
      return;
    }
    const auto& c = acc[noise][label].last_common;
    std::printf("%-10s %4d %-26s %8zu %9.2f %9.3f %6.0f%% %6.3f %8.2fx %8.2fx %8.2fx %8.2fx\n", noise.c_str(), seed,
                label.c_str(), r.events, r.position_rms_mm, r.orientation_rms_deg, 100 * r.coverage, r.first_estimate,
                sw.ok ? r.position_rms_mm / sw.position_rms_mm : 0.0,
                sw.ok ? r.orientation_rms_deg / sw.orientation_rms_deg : 0.0, c.first, c.second);
    std::fflush(stdout);
  };
  auto attempt = [&](const std::string& cmd, const std::string& dir) {
    try
    {
      runCommand(cmd + " >/dev/null", log);
      return trackAndScore(tools, dir, log);
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "benchmark_screen_loop --tracker: %s\n", e.what());
      return RunResult();
    }
  };
  for (const auto& noise : presets)
  {
    // A preset without any random part (clean) gives the same events for every seed.
    const NoiseConfig n = noisePreset(noise);
    const bool random = n.threshold_sigma > 0 || n.latency_jitter > 0 || n.background_rate > 0 ||
                        (n.hot_pixel_fraction > 0 && n.hot_pixel_rate > 0) || n.random_initial_reference;
    for (int seed = 0; seed < (random ? seeds : 1); ++seed)
    {
      const std::string cfg = work + "/noise_" + noise + ".yaml";
      std::ofstream(cfg) << "events: {noise: {preset: " << noise << "}}\n";
      const std::string common = " --scenario " + quote(scenario) + " --seed " + std::to_string(seed);
      const std::string sw_dir = work + "/" + noise + "_seed" + std::to_string(seed) + "_software";
      const RunResult sw =
          attempt(quote(tools.simulate) + common + " --config " + quote(cfg) + " --out " + quote(sw_dir), sw_dir);
      report(noise, seed, "pure software", sw, sw);
      for (double s : time_scales)
      {
        char label[64];
        std::snprintf(label, sizeof(label), "screen in the loop, S=%g", s);
        char scale[32];
        std::snprintf(scale, sizeof(scale), "%g", s);
        const std::string dir = work + "/" + noise + "_seed" + std::to_string(seed) + "_screen_S" + scale;
        char opts[128];
        std::snprintf(opts, sizeof(opts), " --time-scale %.10g --response-ms %.10g", s, response_ms);
        const RunResult r = attempt(quote(tools.emulate) + common + opts + " --config " + quote(cfg) + " --out " + quote(dir), dir);
        report(noise, seed, label, r, sw);
        const NoiseConfig base = noisePreset(noise);
        if (base.background_rate == 0 && base.hot_pixel_rate == 0)
          continue;
        // The same sensor slowed by S in software: its noise per trajectory second and its time
        // constants in trajectory time, as the screen in the loop gives them.
        NoiseConfig slowed = base;
        slowed.background_rate *= s;
        slowed.hot_pixel_rate *= s;
        slowed.refractory_period /= s;
        slowed.latency /= s;
        slowed.latency_jitter /= s;
        const std::string scfg = work + "/noise_" + noise + "_slowed_S" + scale + ".yaml";
        std::ofstream(scfg) << noiseYaml(slowed);
        const std::string sdir = work + "/" + noise + "_seed" + std::to_string(seed) + "_software_slowed_S" + scale;
        std::snprintf(label, sizeof(label), "software, sensor S=%g", s);
        const RunResult rs =
            attempt(quote(tools.simulate) + common + " --config " + quote(scfg) + " --out " + quote(sdir), sdir);
        report(noise, seed, label, rs, sw);
      }
    }
  }
  std::printf("\nmedians over seeds (ratios: per seed, to the same seed's pure-software run, then the median)\n");
  std::printf("%-10s %-26s %8s %9s %9s %7s %9s %9s %9s %9s %6s\n", "noise", "run", "events", "pos_rms", "ori_rms",
              "tracked", "pos_ratio", "ori_ratio", "pos_comm", "ori_comm", "failed");
  int failures = 0;
  for (const auto& [noise, label] : order)
  {
    const Acc& a = acc[noise][label];
    failures += a.failed;
    std::printf("%-10s %-26s %8.0f %9.2f %9.3f %6.0f%% %8.2fx %8.2fx %8.2fx %8.2fx %6d\n", noise.c_str(), label.c_str(),
                median(a.events), median(a.pos), median(a.ori), 100 * median(a.cov), median(a.pos_ratio),
                median(a.ori_ratio), median(a.common_pos_ratio), median(a.common_ori_ratio), a.failed);
  }
  return failures == 0 ? 0 : 1;
}
}  // namespace dvs_screen_sim
