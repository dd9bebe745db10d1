#pragma once
// One event-validation step for every input path (ROS-free): counts events outside the sensor,
// time stamps that go backwards (and by how much), and exact duplicates, so that nothing wrong in
// an input passes (or is dropped or repaired) without a count and a message. O(1) per event, no
// allocation.
//
// Usage:
//   dvs_driver::EventValidator v(width, height);     // 0 x 0: sensor unknown, no outside check
//   v.check(events.data(), events.data() + events.size());   // or v.check(e) per event
//   v.dropOutside(events, first);                     // or drop the events outside, counted
//   if (!v.checks().clean()) warn(name + ": " + v.checks().summary());
//   json += v.checks().json();                        // "outside_sensor":..,"backwards":..,...
// Readers that repair or drop input themselves (the AEDAT reader clamps backwards time stamps and
// skips records outside the sensor) report it in the same EventChecks (clamped, outside_sensor).
#include <dvs_driver/event.h>

#include <cstdint>
#include <climits>
#include <string>

namespace dvs_driver
{
/// What a validation found (cumulative). All zero = clean.
struct EventChecks
{
  uint64_t events = 0;          ///< events checked
  uint64_t outside_sensor = 0;  ///< events (or records) with a pixel outside the sensor
  uint64_t backwards = 0;       ///< events earlier than the event before them
  int64_t max_backwards_ns = 0; ///< the largest such step back
  uint64_t clamped = 0;         ///< event times raised to the latest time before them (repaired)
  uint64_t duplicates = 0;      ///< exact copies (time, pixel, polarity) of an event at the same time
  uint32_t width = 0, height = 0;  ///< the sensor checked against (0: unknown)

  /// Real DVS128 recordings hold a few exact duplicates (0 to 0.7 % of the events of the
  /// recordings in ../shared/data/real); more than this fraction means a duplicated input.
  static constexpr double kDuplicateWarnFraction = 0.01;
  /// Nothing to warn about: no event outside the sensor, backwards or clamped, and duplicates
  /// at most kDuplicateWarnFraction of the events checked.
  bool clean() const
  {
    return outside_sensor == 0 && backwards == 0 && clamped == 0 &&
           static_cast<double>(duplicates) <= kDuplicateWarnFraction * static_cast<double>(events);
  }
  /// Adds the counts of `o` (the largest step back of both).
  void merge(const EventChecks& o);
  /// Every non-zero counter, e.g. "3 events outside the 128x128 sensor, 2 time stamps going
  /// backwards (by up to 0.0015 s), 5 event times clamped to the time before them, 10 exact
  /// duplicates (50% of 20 events)"; "" when all are zero.
  std::string summary() const;
  /// The counters as JSON members (no braces): "outside_sensor":N,"backwards":N,
  /// "max_backwards_s":S,"clamped":N,"duplicates":N
  std::string json() const;
};

class EventValidator
{
public:
  /// Sensor width x height; 0 x 0 = unknown (no outside check).
  explicit EventValidator(uint32_t width = 0, uint32_t height = 0) { setSensor(width, height); }
  void setSensor(uint32_t width, uint32_t height)
  {
    checks_.width = width;
    checks_.height = height;
  }

  /// Checks one event (in delivery order); returns false when it lies outside the sensor.
  bool check(const Event& e)
  {
    ++checks_.events;
    checkTimeAndDuplicate(e);
    if (checks_.width != 0 && (e.x >= checks_.width || e.y >= checks_.height))
    {
      ++checks_.outside_sensor;
      return false;
    }
    return true;
  }
  void check(const Event* begin, const Event* end)
  {
    for (const Event* e = begin; e != end; ++e)
      check(*e);
  }
  /// Checks events[first, end) and removes those outside the sensor (in place, order kept).
  /// Returns how many were removed.
  size_t dropOutside(EventVector& events, size_t first = 0);

  /// Only the time: counts a step back from the previous time (readers that see times before
  /// they repair them).
  void checkTime(int64_t t_ns)
  {
    if (has_last_ && t_ns < last_t_)
    {
      ++checks_.backwards;
      // The step in unsigned arithmetic: exact for any two int64 times (no signed overflow).
      const uint64_t back = static_cast<uint64_t>(last_t_) - static_cast<uint64_t>(t_ns);
      const int64_t step = back > static_cast<uint64_t>(INT64_MAX) ? INT64_MAX : static_cast<int64_t>(back);
      if (step > checks_.max_backwards_ns)
        checks_.max_backwards_ns = step;
    }
    has_last_ = true;
    last_t_ = t_ns;
  }
  /// A reader repaired (clamped) `n` event times / skipped `n` records outside the sensor.
  void countClamped(uint64_t n = 1) { checks_.clamped += n; }
  void countOutside(uint64_t n = 1) { checks_.outside_sensor += n; }

  const EventChecks& checks() const { return checks_; }
  /// Forget the counts and the previous event (a new pass over an input); keeps the sensor.
  void reset();

private:
  void checkTimeAndDuplicate(const Event& e)
  {
    const bool same_time = has_last_ && e.t_ns == last_t_;
    checkTime(e.t_ns);
    if (!same_time)
    {
      recent_[0] = e;
      recent_n_ = 1;
      recent_next_ = 1;
      return;
    }
    for (unsigned i = 0; i < recent_n_; ++i)
      if (recent_[i] == e)
      {
        ++checks_.duplicates;
        return;
      }
    recent_[recent_next_] = e;
    recent_next_ = (recent_next_ + 1) % kRecent;
    if (recent_n_ < kRecent)
      ++recent_n_;
  }

  static constexpr unsigned kRecent = 16;  ///< events of the current time stamp compared against
  EventChecks checks_;
  bool has_last_ = false;
  int64_t last_t_ = 0;
  Event recent_[kRecent];
  unsigned recent_n_ = 0, recent_next_ = 0;
};

/// A whole stream read at once (readEventsText, readEventsBag, readAedat(...).stream): its events
/// checked against s.width x s.height (0: no outside check), merged with what the reader
/// repaired or dropped itself (`repaired`: AedatInfo::checks; nothing for text and bags).
EventChecks validateStream(const EventStream& s, const EventChecks& repaired = EventChecks());
}  // namespace dvs_driver
