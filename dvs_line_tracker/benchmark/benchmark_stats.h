#pragma once
// The small statistics every tracker benchmark prints: thread CPU time, median, percentile, worst.
#include <algorithm>
#include <ctime>
#include <vector>

namespace dvs_line_tracker
{
/// CPU time of the calling thread [s] (other processes on a shared machine do not count). A
/// system call: read it around loops, not per event.
inline double threadCpuSeconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/// Median (the mean of the two middle values for an even count); `if_empty` for none.
inline double median(std::vector<double> v, double if_empty = 0.0)
{
  if (v.empty())
    return if_empty;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// The q-quantile (0..1) by rank, reordering `v`; 0 for none.
inline double percentile(std::vector<double>& v, double q)
{
  if (v.empty())
    return 0.0;
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + i, v.end());
  return v[i];
}

/// The largest / smallest value; 0 for none.
inline double maxOf(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
inline double minOf(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }
}  // namespace dvs_line_tracker
