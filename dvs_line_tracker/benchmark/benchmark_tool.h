#pragma once
// Plumbing shared by the tracker benchmarks (ROS-free): whole-number options, `--params
// tracker.yaml` and an output folder, each failing with a message that names the program (the callers exit with 2 / 1), and
// a work queue over `--jobs` threads.
#include <dvs_line_tracker/tracker_params.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace dvs_line_tracker
{
/// A whole number in [lo, hi] (decimal, nothing else in `text`) into `out`; false otherwise
/// (an empty text too).
inline bool parseIntInRange(const std::string& text, int lo, int hi, int& out)
{
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || !end || *end || v < lo || v > hi)
    return false;
  out = static_cast<int>(v);
  return true;
}

/// loadTrackerParamsYaml(path, params); false (the error printed as "program: what") when the
/// file is missing or wrong.
inline bool loadParamsOption(const char* program, const char* path, LineTrackerParams& params)
{
  try
  {
    loadTrackerParamsYaml(path, params);
    return true;
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "%s: %s\n", program, e.what());
    return false;
  }
}

/// Creates `dir` (and its parents); false (the error printed as "program: option dir: cannot
/// create the folder: why") when that fails.
inline bool createOutputFolder(const char* program, const char* option, const std::string& dir)
{
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!ec)
    return true;
  std::fprintf(stderr, "%s: %s %s: cannot create the folder: %s\n", program, option, dir.c_str(), ec.message().c_str());
  return false;
}

/// The options of the programs that run numbered scenes (benchmark_init_sweep,
/// benchmark_reacquire): --scenes N, --jobs J, --scene I, --dump DIR (needs --scene), --params FILE.
struct SceneOptions
{
  int count = 64;
  int jobs = 2;
  int only = -1;  ///< --scene: only this one
  std::string dump;
  LineTrackerParams params;

  /// The scenes to run: 0 .. count - 1, or `only`.
  std::vector<int> selected() const
  {
    std::vector<int> todo;
    if (only >= 0)
      todo.push_back(only);
    else
      for (int i = 0; i < count; ++i)
        todo.push_back(i);
    return todo;
  }
};

/// Reads argv into `options` (its fields hold the defaults); false on an unknown or bad option
/// (a --params file's error is printed as "program: what"; the caller prints its usage).
inline bool parseSceneOptions(const char* program, int argc, char** argv, SceneOptions& options)
{
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (i + 1 >= argc)
      return false;
    const std::string value = argv[++i];
    bool ok = true;
    if (arg == "--scenes")
      ok = parseIntInRange(value, 1, 10000, options.count);
    else if (arg == "--jobs")
      ok = parseIntInRange(value, 1, 16, options.jobs);
    else if (arg == "--scene")
      ok = parseIntInRange(value, 0, 9999, options.only);
    else if (arg == "--dump")
      options.dump = value;
    else if (arg == "--params")
      ok = loadParamsOption(program, value.c_str(), options.params);
    else
      ok = false;
    if (!ok)
      return false;
  }
  return options.dump.empty() || options.only >= 0;
}

/// Calls job(0) ... job(count - 1), each once, on min(jobs, count) threads taking the next index
/// as they finish (`job` must not throw).
template <typename Job>
void runJobs(size_t count, int jobs, const Job& job)
{
  std::atomic<size_t> next{0};
  auto worker = [&]() {
    for (size_t k = next++; k < count; k = next++)
      job(k);
  };
  std::vector<std::thread> threads;
  for (size_t t = 0; t < std::min(static_cast<size_t>(std::max(jobs, 1)), count); ++t)
    threads.emplace_back(worker);
  for (auto& t : threads)
    t.join();
}

/// Runs work(i) for every scene index i of `todo` on `jobs` threads (runJobs); the message of an
/// exception it throws goes into errors[i] (sized for the largest index); "scene i done" on stderr
/// after each.
template <typename Work>
void runScenes(const std::vector<int>& todo, int jobs, std::vector<std::string>& errors, const Work& work)
{
  runJobs(todo.size(), jobs, [&](size_t k) {
    const int i = todo[k];
    try
    {
      work(i);
    }
    catch (const std::exception& e)
    {
      errors[i] = e.what();
    }
    std::fprintf(stderr, "scene %d done\n", i);
  });
}
}  // namespace dvs_line_tracker
