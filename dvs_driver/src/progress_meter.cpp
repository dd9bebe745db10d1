#include <dvs_driver/progress_meter.h>

#include <time.h>
#include <unistd.h>

namespace dvs_driver
{
namespace
{
double monotonicSeconds()
{
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

std::string thousands(uint64_t v)
{
  std::string digits = std::to_string(v), out;
  for (size_t i = 0; i < digits.size(); ++i)
  {
    if (i > 0 && (digits.size() - i) % 3 == 0)
      out += ',';
    out += digits[i];
  }
  return out;
}

std::string scaled(double v, const char* const units[], int n_units, double step)
{
  int u = 0;
  while (u + 1 < n_units && v >= step)
  {
    v /= step;
    ++u;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.1f %s", v, units[u]);
  return buf;
}
}  // namespace

std::string formatProgress(const std::string& label, uint64_t events, uint64_t bytes_done, uint64_t total_bytes,
                           double seconds, ProgressTotal unit)
{
  std::string s = label + ": " + thousands(events) + " events";
  if (total_bytes > 0)
  {
    const double pct = bytes_done >= total_bytes ? 100.0 : 100.0 * double(bytes_done) / double(total_bytes);
    static const char* const sizes[] = {"bytes", "kB", "MB", "GB", "TB"};
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f %% of ", pct);
    s += ", " + std::string(buf) +
         (unit == ProgressTotal::Events ? thousands(total_bytes) + " events" : scaled(double(total_bytes), sizes, 5, 1000.0));
  }
  if (seconds > 0)
  {
    static const char* const rates[] = {"events/s", "k events/s", "M events/s", "G events/s"};
    s += ", " + scaled(double(events) / seconds, rates, 4, 1000.0);
  }
  return s;
}

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

ProgressMeter::ProgressMeter(std::string label, uint64_t total_bytes, bool enabled, double min_interval_s,
                             std::FILE* out)
  : label_(std::move(label)), total_(total_bytes), enabled_(enabled), interval_(min_interval_s), out_(out)
{
  start_ = last_ = monotonicSeconds();
}

void ProgressMeter::update(uint64_t events, uint64_t bytes_done)
{
  if (!enabled_)
    return;
  const double now = monotonicSeconds();
  if (now - last_ < interval_)
    return;
  last_ = now;
  print(events, bytes_done, false);
}

void ProgressMeter::finish(uint64_t events, uint64_t bytes_done)
{
  if (enabled_ && lines_ > 0)
    print(events, bytes_done, true);
}

ReadProgress ProgressMeter::callback()
{
  return [this](uint64_t events, uint64_t bytes_done, uint64_t bytes_total) {
    if (bytes_total > 0)
      total_ = bytes_total;
    update(events, bytes_done);
  };
}

WriteProgress ProgressMeter::writeCallback()
{
  return [this](uint64_t events) { update(events, events); };
}

void ProgressMeter::print(uint64_t events, uint64_t bytes_done, bool last)
{
  const std::string line = formatProgress(label_, events, bytes_done, total_, monotonicSeconds() - start_, unit_);
  // "\r" back to the line's start, "\x1b[K" clears what a longer earlier line left.
  std::fprintf(out_, "\r%s\x1b[K%s", line.c_str(), last ? "\n" : "");
  std::fflush(out_);
  ++lines_;
}
}  // namespace dvs_driver
