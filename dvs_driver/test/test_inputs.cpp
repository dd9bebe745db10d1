// ROS-free parts of the driver: stamp mapping, packet policy, file replay input.
#include <dvs_driver/file_replay.h>
#include <dvs_driver/packet_builder.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

using dvs_driver::Event;

TEST(StampMapper, BasePlusTimeAndNeverBackwards)
{
  dvs_driver::StampMapper m;
  m.setBase(1000000000000LL);
  EXPECT_EQ(1000000000500LL, m.map(500));
  EXPECT_EQ(1000000001000LL, m.map(1000));
  // A timestamp reset: new base slightly earlier than the last stamp -> clamped, counted.
  m.setBase(1000000000800LL);
  EXPECT_EQ(1000000001000LL, m.map(0));
  EXPECT_EQ(1u, m.clamped());
  EXPECT_EQ(1000000001300LL, m.map(500));
  EXPECT_EQ(1u, m.clamped());
}

TEST(PacketPolicy, PeriodOrCount)
{
  dvs_driver::PacketPolicy p;
  p.period_ns = 1000000;
  p.max_events = 3;
  EXPECT_FALSE(p.full(0, 999999, 1));
  EXPECT_TRUE(p.full(0, 1000000, 1));
  EXPECT_TRUE(p.full(0, 10, 3));
  EXPECT_FALSE(p.full(0, 10, 2));
}

namespace
{
struct Collect : dvs_driver::EventInputListener
{
  std::mutex mutex;
  std::condition_variable cv;
  dvs_driver::EventVector events;
  size_t chunks = 0;
  int64_t max_chunk_span = 0;
  bool ended = false;
  void onEvents(const Event* b, const Event* e) override
  {
    std::lock_guard<std::mutex> lock(mutex);
    events.insert(events.end(), b, e);
    ++chunks;
    max_chunk_span = std::max(max_chunk_span, (e - 1)->t_ns - b->t_ns);
  }
  void onEndOfInput() override
  {
    std::lock_guard<std::mutex> lock(mutex);
    ended = true;
    cv.notify_all();
  }
  bool waitEnd()
  {
    std::unique_lock<std::mutex> lock(mutex);
    return cv.wait_for(lock, std::chrono::seconds(20), [this] { return ended; });
  }
};

dvs_driver::EventStream makeStream(size_t n, int64_t dt_ns)
{
  dvs_driver::EventStream s;
  s.width = 128;
  s.height = 128;
  for (size_t i = 0; i < n; ++i)
    s.events.push_back(Event{static_cast<int64_t>(i) * dt_ns - 5000, static_cast<uint16_t>(i % 128),
                             static_cast<uint16_t>(i / 128 % 128), i % 2 == 0});
  return s;
}

std::unique_ptr<dvs_driver::EventSource> memory(const dvs_driver::EventStream& s)
{
  return std::unique_ptr<dvs_driver::EventSource>(new dvs_driver::MemoryEventSource(s, "memory"));
}
}  // namespace

TEST(FileReplay, FullSpeedDeliversEverythingInBoundedChunks)
{
  const auto s = makeStream(50000, 1000);  // 50 ms of events, 1 us apart
  dvs_driver::FileReplayOptions o;
  o.speed = 0;
  o.chunk_period_ns = 100000;
  o.chunk_max_events = 64;
  dvs_driver::FileReplay in(memory(s), o);
  Collect c;
  in.start(c);
  ASSERT_TRUE(c.waitEnd());
  in.stop();
  ASSERT_EQ(s.events.size(), c.events.size());
  for (size_t i = 0; i < s.events.size(); ++i)
    ASSERT_EQ(s.events[i], c.events[i]) << i;
  EXPECT_EQ((50000u + 63) / 64, c.chunks);  // 64 events span 63 us < 100 us: the count limits
  EXPECT_LT(c.max_chunk_span, o.chunk_period_ns);
}

TEST(FileReplay, LoopKeepsTimeIncreasingAndStopJoins)
{
  const auto s = makeStream(1000, 1000);
  dvs_driver::FileReplayOptions o;
  o.speed = 0;
  o.loop = true;
  dvs_driver::FileReplay in(memory(s), o);
  Collect c;
  in.start(c);
  while (in.delivered() < 5000)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  in.stop();
  std::lock_guard<std::mutex> lock(c.mutex);
  ASSERT_GE(c.events.size(), 5000u);
  for (size_t i = 1; i < c.events.size(); ++i)
    ASSERT_GT(c.events[i].t_ns, c.events[i - 1].t_ns) << i;
  // The second loop starts one span + 1 ms after the first event.
  EXPECT_EQ(s.events.front().t_ns + 999 * 1000 + 1000000, c.events[1000].t_ns);
  EXPECT_FALSE(c.ended);
}

TEST(FileReplay, RejectsBadOptionsAndHandlesEmptyStreams)
{
  dvs_driver::FileReplayOptions o;
  o.speed = -1;
  EXPECT_THROW(dvs_driver::FileReplay(memory(makeStream(1, 1)), o), std::invalid_argument);
  dvs_driver::FileReplay empty(memory(dvs_driver::EventStream()), dvs_driver::FileReplayOptions());
  Collect c;
  empty.start(c);
  EXPECT_TRUE(c.waitEnd());
  empty.stop();
  EXPECT_TRUE(c.events.empty());
}
