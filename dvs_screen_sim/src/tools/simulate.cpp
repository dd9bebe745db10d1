// simulate: run the software DVS offline and write a dataset folder.
//   simulate --scenario NAME --out DIR [--seed N] [--duration S] [--config FILE.yaml] [--bag]
#include <dvs_screen_sim/bag_output.h>
#include <dvs_screen_sim/dataset.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <cstdlib>
#include <iostream>
#include <string>

namespace
{
void usage(std::ostream& out)
{
  out << "usage: simulate --scenario NAME --out DIR [--seed N] [--duration S] [--config FILE.yaml] [--bag]\n"
         "  NAME: flip | helix | circle | linear | random | file\n"
         "  DIR receives events.txt, groundtruth.txt, imu.txt, imu_bias_groundtruth.txt, calib.txt,\n"
         "  camera_info.yaml, map.yaml, config.yaml\n"
         "  (and events.bag with --bag). --config overrides any parameter (see the package README).\n";
}

bool parseUnsigned(const std::string& s, uint64_t& v)
{
  if (s.empty() || s[0] == '-')
    return false;
  char* end = nullptr;
  v = std::strtoull(s.c_str(), &end, 10);
  return end && *end == '\0';
}

bool parseDouble(const std::string& s, double& v)
{
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0';
}
}  // namespace

int main(int argc, char** argv)
{
  std::string scenario, out_dir, config_path;
  std::optional<uint64_t> seed;
  std::optional<double> duration;
  bool bag = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc)
      {
        std::cerr << "simulate: " << name << " needs a value\n";
        usage(std::cerr);
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--scenario")
      scenario = value("--scenario");
    else if (arg == "--out")
      out_dir = value("--out");
    else if (arg == "--config")
      config_path = value("--config");
    else if (arg == "--seed")
    {
      uint64_t v;
      const std::string s = value("--seed");
      if (!parseUnsigned(s, v))
      {
        std::cerr << "simulate: --seed must be a non-negative integer (got '" << s << "')\n";
        return 2;
      }
      seed = v;
    }
    else if (arg == "--duration")
    {
      double v;
      const std::string s = value("--duration");
      if (!parseDouble(s, v) || !(v > 0))
      {
        std::cerr << "simulate: --duration must be a positive number of seconds (got '" << s << "')\n";
        return 2;
      }
      duration = v;
    }
    else if (arg == "--bag")
      bag = true;
    else if (arg == "-h" || arg == "--help")
    {
      usage(std::cout);
      return 0;
    }
    else
    {
      std::cerr << "simulate: unknown argument '" << arg << "'\n";
      usage(std::cerr);
      return 2;
    }
  }
  if (scenario.empty() || out_dir.empty())
  {
    std::cerr << "simulate: --scenario and --out are required\n";
    usage(std::cerr);
    return 2;
  }
  try
  {
    const dvs_screen_sim::SimConfig config = dvs_screen_sim::resolveSimConfigFile(scenario, config_path, seed, duration);
    // Events are streamed to the files chunk by chunk: memory stays bounded for long runs.
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec)
      throw std::runtime_error("cannot create output folder '" + out_dir + "': " + ec.message());
    dvs_screen_sim::EventsTextStream text(out_dir + "/events.txt");
    std::unique_ptr<dvs_screen_sim::SimulationBagWriter> bag_writer;
    if (bag)
      bag_writer = std::make_unique<dvs_screen_sim::SimulationBagWriter>(out_dir + "/events.bag", config);
    const dvs_screen_sim::SimulationOutput output =
        dvs_screen_sim::runSimulation(config, [&](const dvs_driver::EventVector& chunk) {
          text.write(chunk);
          if (bag_writer)
            bag_writer->addEvents(chunk);
        });
    text.close();
    dvs_screen_sim::writeDatasetWithoutEvents(out_dir, config, output.groundtruth);
    dvs_screen_sim::writeImuFiles(out_dir, output);
    if (bag_writer)
      bag_writer->finish(output.groundtruth, output.imu);
    std::printf("simulate: %s, %.3f s simulated, %llu events (%llu noise), %llu samples, %zu IMU samples, %.3f s CPU "
                "(%.2fx real time) -> %s\n",
                scenario.c_str(), config.duration, static_cast<unsigned long long>(output.event_count),
                static_cast<unsigned long long>(output.stats.noise_events),
                static_cast<unsigned long long>(output.stats.samples), output.imu.size(), output.cpu_seconds,
                output.cpu_seconds > 0 ? config.duration / output.cpu_seconds : 0.0, out_dir.c_str());
  }
  catch (const std::exception& e)
  {
    std::cerr << "simulate: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
