// The one event-validation step (event_validation.h) and every dvs_driver input path that applies
// it: known answers for the counters; the AEDAT reader counts (and still clamps) backwards times
// and records outside the sensor, whole and streamed; a garbage AEDAT file is reported; the file
// replay of the driver counts, drops events outside the sensor, and warns, for memory, AEDAT,
// events.txt (duplicated lines) and bag (decreasing times) sources.
#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/event_validation.h>
#include <dvs_driver/file_replay.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>

#include <condition_variable>
#include <fstream>
#include <mutex>
#include <random>
#include <string>
#include <unistd.h>

using dvs_driver::Event;
using dvs_driver::EventChecks;
using dvs_driver::EventValidator;

namespace
{
std::string tmp(const std::string& name)
{
  return "/tmp/dvs_validation_test_" + std::to_string(::getpid()) + "_" + name;
}

// AEDAT 2.0 bytes: a DVS128 header and records {address, time in us}.
std::string aedat(const std::vector<std::pair<uint32_t, int32_t>>& records)
{
  std::string b = "#!AER-DAT2.0\r\n# AEChip: ch.unizh.ini.jaer.chip.retina.DVS128\r\n";
  for (const auto& r : records)
    for (const uint32_t v : {r.first, static_cast<uint32_t>(r.second)})
      for (int shift = 24; shift >= 0; shift -= 8)
        b.push_back(static_cast<char>((v >> shift) & 0xFF));
  return b;
}

// DVS128 address of pixel (x, y), ON.
uint32_t dvs128(uint32_t x, uint32_t y)
{
  return ((127 - y) << 8) | ((127 - x) << 1);
}

void writeFile(const std::string& path, const std::string& bytes)
{
  std::ofstream(path, std::ios::binary) << bytes;
}

// Collects a replay's events and warnings, and waits for its end.
struct Collector : dvs_driver::EventInputListener
{
  std::mutex m;
  std::condition_variable cv;
  dvs_driver::EventVector events;
  std::vector<std::string> warnings;
  bool done = false;
  std::string error;
  void onEvents(const Event* b, const Event* e) override
  {
    std::lock_guard<std::mutex> l(m);
    events.insert(events.end(), b, e);
  }
  void onWarning(const std::string& w) override
  {
    std::lock_guard<std::mutex> l(m);
    warnings.push_back(w);
  }
  void onEndOfInput() override
  {
    std::lock_guard<std::mutex> l(m);
    done = true;
    cv.notify_all();
  }
  void onInputError(const std::string& message) override
  {
    std::lock_guard<std::mutex> l(m);
    error = message;
    done = true;
    cv.notify_all();
  }
  void wait()
  {
    std::unique_lock<std::mutex> l(m);
    ASSERT_TRUE(cv.wait_for(l, std::chrono::seconds(60), [&] { return done; }));
  }
};

// Plays a source to its end as fast as possible.
EventChecks replay(std::unique_ptr<dvs_driver::EventSource> source, Collector& c, uint32_t w = 0, uint32_t h = 0)
{
  dvs_driver::FileReplayOptions o;
  o.speed = 0;
  o.read_block = 7;  // blocks and chunks split the duplicates and steps back
  o.sensor_width = w;
  o.sensor_height = h;
  dvs_driver::FileReplay r(std::move(source), o);
  r.start(c);
  c.wait();
  r.stop();
  return r.checks();
}
}  // namespace

TEST(EventValidator, KnownAnswers)
{
  EventValidator v(128, 128);
  const std::vector<Event> ev = {
      {100, 1, 1, true},  {100, 2, 1, true},  {100, 1, 1, true},  // duplicate of the first (not adjacent)
      {100, 1, 1, false},                                          // other polarity: not a duplicate
      {200, 128, 5, true},                                         // outside (x)
      {150, 3, 3, true},                                           // back by 50
      {160, 3, 200, true},                                         // outside (y)
      {90, 4, 4, true},                                            // back by 70
      {90, 4, 4, true},                                            // duplicate
      {300, 5, 5, true}};
  size_t inside = 0;
  for (const Event& e : ev)
    inside += v.check(e) ? 1 : 0;
  const EventChecks& c = v.checks();
  EXPECT_EQ(8u, inside);
  EXPECT_EQ(10u, c.events);
  EXPECT_EQ(2u, c.outside_sensor);
  EXPECT_EQ(2u, c.backwards);
  EXPECT_EQ(70, c.max_backwards_ns);
  EXPECT_EQ(2u, c.duplicates);
  EXPECT_EQ(0u, c.clamped);
  EXPECT_FALSE(c.clean());
  EXPECT_EQ("2 events outside the 128x128 sensor, 2 time stamps going backwards (by up to 7e-08 s), "
            "2 exact duplicates (20% of 10 events)",
            c.summary());
  EXPECT_EQ("\"outside_sensor\":2,\"backwards\":2,\"max_backwards_s\":0.000000070,\"clamped\":0,\"duplicates\":2",
            c.json());

  // dropOutside: in place, order kept, counted.
  EventValidator d(128, 128);
  dvs_driver::EventVector copy(ev.begin(), ev.end());
  EXPECT_EQ(2u, d.dropOutside(copy));
  ASSERT_EQ(8u, copy.size());
  EXPECT_EQ((Event{150, 3, 3, true}), copy[4]);
  EXPECT_EQ(2u, d.checks().outside_sensor);

  // Extreme times: the step back saturates instead of overflowing.
  EventValidator x;
  x.check(Event{INT64_MAX, 0, 0, true});
  x.check(Event{INT64_MIN, 0, 0, true});
  EXPECT_EQ(INT64_MAX, x.checks().max_backwards_ns);

  // Unknown sensor: no outside check. reset() forgets the previous event.
  EventValidator u;
  u.check(Event{5, 60000, 60000, true});
  u.reset();
  u.check(Event{1, 0, 0, true});
  EXPECT_TRUE(u.checks().clean());
  EXPECT_EQ("", u.checks().summary());
}

TEST(EventValidator, FewDuplicatesAreNormalManyAreNot)
{
  // Real DVS128 recordings hold up to ~0.7% exact duplicates: counted, not warned about.
  EventValidator v(128, 128);
  for (int i = 0; i < 1000; ++i)
    v.check(Event{i * 10, 1, 1, true});
  for (int i = 0; i < 5; ++i)
    v.check(Event{10000, 1, 1, true});
  EXPECT_EQ(4u, v.checks().duplicates);
  EXPECT_TRUE(v.checks().clean());
  EXPECT_NE(std::string::npos, v.checks().summary().find("4 exact duplicates")) << v.checks().summary();
  // Every event twice: 50%.
  EventValidator all(128, 128);
  for (int i = 0; i < 100; ++i)
    for (int k = 0; k < 2; ++k)
      all.check(Event{i * 10, 1, 1, true});
  EXPECT_EQ(100u, all.checks().duplicates);
  EXPECT_FALSE(all.checks().clean());
}

TEST(AedatValidation, BackwardsTimesAreClampedCountedAndReported)
{
  // Times 10, 20, 5 (back by 15), 6, 30, 25 (back by 5); one address beyond 16 bits.
  const std::string bytes = aedat({{dvs128(1, 1), 10},
                                   {dvs128(2, 1), 20},
                                   {dvs128(3, 1), 5},
                                   {dvs128(4, 1), 6},
                                   {0x12345678u, 7},
                                   {dvs128(5, 1), 30},
                                   {dvs128(6, 1), 25}});
  const auto rec = dvs_driver::readAedat(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), "back.aedat");
  ASSERT_EQ(6u, rec.stream.events.size());
  EXPECT_EQ(20000, rec.stream.events[2].t_ns);  // clamped, as before
  EXPECT_EQ(3u, rec.info.non_monotonic);
  const EventChecks& c = rec.info.checks;
  EXPECT_EQ(2u, c.backwards);
  EXPECT_EQ(15000, c.max_backwards_ns);
  EXPECT_EQ(3u, c.clamped);
  EXPECT_EQ(1u, c.outside_sensor);
  EXPECT_EQ(1u, rec.info.out_of_range);
  EXPECT_FALSE(c.clean());
  // The whole-stream helper merges the reader's repairs with the events' own checks.
  const EventChecks all = dvs_driver::validateStream(rec.stream, rec.info.checks);
  EXPECT_EQ(6u, all.events);
  EXPECT_EQ(2u, all.backwards);  // the reader's (the clamped events do not go back)
  EXPECT_EQ(3u, all.clamped);
  EXPECT_EQ(1u, all.outside_sensor);
  EXPECT_EQ("1 event outside the 128x128 sensor, 2 time stamps going backwards (by up to 1.5e-05 s), "
            "3 event times clamped to the time before them",
            c.summary());

  // Streamed (AedatFileSource, any block size): the same counts, reset by rewind.
  const std::string path = tmp("back.aedat");
  writeFile(path, bytes);
  dvs_driver::AedatFileSource src(path);
  dvs_driver::EventVector out;
  while (src.read(out, 2) > 0)
  {
  }
  EXPECT_EQ(2u, src.checks().backwards);
  EXPECT_EQ(15000, src.checks().max_backwards_ns);
  EXPECT_EQ(3u, src.checks().clamped);
  EXPECT_EQ(1u, src.checks().outside_sensor);
  src.rewind();
  EXPECT_TRUE(src.checks().clean());

  // The driver's replay reports them (merged with its own checks) and warns.
  Collector col;
  const EventChecks played = replay(dvs_driver::openEventSource(path), col);
  EXPECT_EQ(6u, col.events.size());
  EXPECT_EQ(3u, played.clamped);
  EXPECT_EQ(2u, played.backwards);
  EXPECT_EQ(1u, played.outside_sensor);
  ASSERT_FALSE(col.warnings.empty());
  EXPECT_NE(std::string::npos, col.warnings.back().find(path + ": 1 event outside the 128x128 sensor")) << col.warnings.back();
  EXPECT_NE(std::string::npos, col.warnings.back().find("3 event times clamped")) << col.warnings.back();
  std::remove(path.c_str());
}

TEST(AedatValidation, GarbageIsReportedNotACleanZero)
{
  std::mt19937 rng(7);
  std::vector<std::pair<uint32_t, int32_t>> records;
  for (int i = 0; i < 5000; ++i)
    records.emplace_back(static_cast<uint32_t>(rng()), static_cast<int32_t>(rng()));
  const std::string bytes = aedat(records);
  const auto rec = dvs_driver::readAedat(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), "garbage.aedat");
  EXPECT_EQ(5000u, rec.info.records);
  EXPECT_GT(rec.info.out_of_range, 4900u);
  EXPECT_EQ(rec.info.out_of_range, rec.info.checks.outside_sensor);
  EXPECT_FALSE(rec.info.checks.clean());
  EXPECT_NE(std::string::npos, rec.info.checks.summary().find("events outside the 128x128 sensor"));
}

TEST(ReplayValidation, DropsOutsideCountsTheRestAndWarns)
{
  dvs_driver::EventStream s;
  s.width = 128;
  s.height = 128;
  for (int i = 0; i < 100; ++i)
    s.events.push_back(Event{1000 + i * 1000, static_cast<uint16_t>(i % 128), 3, true});
  s.events[10].x = 500;                         // outside: dropped
  s.events[20] = s.events[19];                  // duplicate: kept
  s.events[30].t_ns = s.events[29].t_ns - 400;  // back by 400 ns: kept
  Collector c;
  const EventChecks k = replay(std::unique_ptr<dvs_driver::EventSource>(new dvs_driver::MemoryEventSource(s, "mem")), c);
  EXPECT_EQ(99u, c.events.size());
  for (const Event& e : c.events)
    EXPECT_LT(e.x, 128);
  EXPECT_EQ(100u, k.events);
  EXPECT_EQ(1u, k.outside_sensor);
  EXPECT_EQ(1u, k.duplicates);
  EXPECT_EQ(1u, k.backwards);
  EXPECT_EQ(400, k.max_backwards_ns);
  ASSERT_FALSE(c.warnings.empty());
  EXPECT_EQ("mem: 1 event outside the 128x128 sensor, 1 time stamp going backwards (by up to 4e-07 s), "
            "1 exact duplicate (1% of 100 events) (in all)",
            c.warnings.back());

  // A clean source: no warning, clean counts.
  s.events[10].x = 1;
  s.events[20].t_ns = s.events[19].t_ns + 1;
  s.events[30].t_ns = s.events[29].t_ns + 1;
  Collector clean;
  const EventChecks ok =
      replay(std::unique_ptr<dvs_driver::EventSource>(new dvs_driver::MemoryEventSource(s, "mem")), clean);
  EXPECT_TRUE(ok.clean());
  EXPECT_EQ(0u, ok.duplicates + ok.backwards + ok.outside_sensor);
  EXPECT_TRUE(clean.warnings.empty());
  EXPECT_EQ(100u, clean.events.size());
}

TEST(ReplayValidation, DuplicatedLinesOfEventsTxtAreCounted)
{
  const std::string path = tmp("dup.txt");
  {
    std::ofstream out(path);
    for (int i = 0; i < 200; ++i)
      for (int k = 0; k < 2; ++k)  // every line twice
        out << "0." << (100000 + i) << " " << (i % 100) << " 7 1\n";
  }
  Collector c;
  const EventChecks k = replay(dvs_driver::openEventSource(path), c);
  EXPECT_EQ(400u, c.events.size());  // kept
  EXPECT_EQ(200u, k.duplicates);
  EXPECT_FALSE(k.clean());
  ASSERT_FALSE(c.warnings.empty());
  EXPECT_NE(std::string::npos, c.warnings.back().find("200 exact duplicates (50% of 400 events)")) << c.warnings.back();
  std::remove(path.c_str());
}

TEST(ReplayValidation, BagWithDecreasingTimesAndEventsOutsideItsSize)
{
  // Messages in increasing bag time whose events go back in time (a bag recorded from a replay
  // that looped); the second message also holds a pixel beyond its stated 128x128.
  const std::string path = tmp("decreasing.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    dvs_driver::EventStream a, b;
    a.width = b.width = a.height = b.height = 128;
    a.events = {{2000000000, 1, 1, true}, {2000001000, 2, 1, true}};
    b.events = {{1000000000, 3, 1, true}, {1000001000, 300, 1, true}, {1000002000, 4, 1, true}};
    bag.write("/dvs/events", ros::Time(10), *dvs_driver::toMessage(a));
    bag.write("/dvs/events", ros::Time(11), *dvs_driver::toMessage(b));
  }
  Collector c;
  const EventChecks k = replay(dvs_driver::openEventSource(path), c, 128, 128);
  EXPECT_EQ(4u, c.events.size());
  EXPECT_EQ(1u, k.backwards);
  EXPECT_EQ(1000001000, k.max_backwards_ns);
  EXPECT_EQ(1u, k.outside_sensor);
  ASSERT_FALSE(c.warnings.empty());
  EXPECT_NE(std::string::npos, c.warnings.back().find("1 time stamp going backwards (by up to 1.000001 s)"))
      << c.warnings.back();
  std::remove(path.c_str());
}
