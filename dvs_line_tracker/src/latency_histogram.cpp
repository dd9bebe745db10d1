#include <dvs_line_tracker/latency_histogram.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dvs_line_tracker
{
namespace
{
constexpr int kBins = LatencyHistogram::kBinsPerOctave * LatencyHistogram::kOctaves;

double upperEdge(int bin)
{
  return LatencyHistogram::kMinSeconds *
         std::exp2(double(bin + 1) / double(LatencyHistogram::kBinsPerOctave));
}
}  // namespace

void LatencyHistogram::add(double seconds, uint64_t weight)
{
  if (weight == 0)
    return;
  if (!(seconds >= 0))  // negative or NaN
  {
    invalid_ += weight;
    return;
  }
  int bin = 0;
  if (seconds > kMinSeconds)
  {
    // bin b holds (kMin 2^(b/16), kMin 2^((b+1)/16)]
    const double b = std::ceil(std::log2(seconds / kMinSeconds) * kBinsPerOctave) - 1.0;
    bin = b >= kBins - 1 ? kBins - 1 : std::max(0, int(b));
  }
  bins_[bin] += weight;
  count_ += weight;
  max_ = std::max(max_, seconds);
}

void LatencyHistogram::reset()
{
  bins_.fill(0);
  count_ = invalid_ = 0;
  max_ = 0;
}

double LatencyHistogram::quantile(double q) const
{
  if (count_ == 0)
    return 0.0;
  // the smallest bin whose cumulative count reaches ceil(q * count)
  const double want = std::max(1.0, std::ceil(std::min(1.0, q) * double(count_)));
  uint64_t seen = 0;
  for (int b = 0; b < kBins; ++b)
  {
    seen += bins_[b];
    if (double(seen) >= want)
      return b == kBins - 1 ? max_ : std::min(upperEdge(b), max_);  // the last bin is open-ended
  }
  return max_;
}

std::string LatencyHistogram::summaryMs() const
{
  if (count_ == 0)
    return "no samples";
  char buf[128];
  std::snprintf(buf, sizeof buf, "p50 / p99 / max = %.3f / %.3f / %.3f ms (%llu)", quantile(0.5) * 1e3,
                quantile(0.99) * 1e3, max_ * 1e3, static_cast<unsigned long long>(count_));
  return buf;
}
}  // namespace dvs_line_tracker
