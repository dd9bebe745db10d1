#include <dvs_driver/event_validation.h>

#include <algorithm>
#include <cstdio>

namespace dvs_driver
{
namespace
{
std::string plural(uint64_t n, const char* one, const char* many)
{
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string seconds(int64_t ns)
{
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.9g", static_cast<double>(ns) * 1e-9);
  return buf;
}
}  // namespace

void EventChecks::merge(const EventChecks& o)
{
  events += o.events;
  outside_sensor += o.outside_sensor;
  backwards += o.backwards;
  max_backwards_ns = std::max(max_backwards_ns, o.max_backwards_ns);
  clamped += o.clamped;
  duplicates += o.duplicates;
  if (width == 0)
  {
    width = o.width;
    height = o.height;
  }
}

std::string EventChecks::summary() const
{
  std::string s;
  auto add = [&](const std::string& part) { s += (s.empty() ? "" : ", ") + part; };
  if (outside_sensor)
    add(plural(outside_sensor, "event", "events") + " outside the " +
        (width ? std::to_string(width) + "x" + std::to_string(height) + " " : std::string()) + "sensor");
  if (backwards)
    add(plural(backwards, "time stamp", "time stamps") + " going backwards (by up to " + seconds(max_backwards_ns) +
        " s)");
  if (clamped)
    add(plural(clamped, "event time", "event times") + " clamped to the time before them");
  if (duplicates)
  {
    std::string part = plural(duplicates, "exact duplicate", "exact duplicates");
    if (events > 0)
    {
      char buf[64];
      std::snprintf(buf, sizeof(buf), " (%.3g%% of %llu events)", 100.0 * static_cast<double>(duplicates) / events,
                    static_cast<unsigned long long>(events));
      part += buf;
    }
    add(part);
  }
  return s;
}

std::string EventChecks::json() const
{
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "\"outside_sensor\":%llu,\"backwards\":%llu,\"max_backwards_s\":%.9f,\"clamped\":%llu,"
                "\"duplicates\":%llu",
                static_cast<unsigned long long>(outside_sensor), static_cast<unsigned long long>(backwards),
                static_cast<double>(max_backwards_ns) * 1e-9, static_cast<unsigned long long>(clamped),
                static_cast<unsigned long long>(duplicates));
  return buf;
}

size_t EventValidator::dropOutside(EventVector& events, size_t first)
{
  size_t out = first;
  for (size_t i = first; i < events.size(); ++i)
    if (check(events[i]))
    {
      if (out != i)
        events[out] = events[i];
      ++out;
    }
  const size_t dropped = events.size() - out;
  events.resize(out);
  return dropped;
}

EventChecks validateStream(const EventStream& s, const EventChecks& repaired)
{
  EventValidator v(s.width, s.height);
  v.check(s.events.data(), s.events.data() + s.events.size());
  EventChecks c = v.checks();
  c.merge(repaired);
  return c;
}

void EventValidator::reset()
{
  const uint32_t w = checks_.width, h = checks_.height;
  checks_ = EventChecks();
  setSensor(w, h);
  has_last_ = false;
  last_t_ = 0;
  recent_n_ = recent_next_ = 0;
}
}  // namespace dvs_driver
