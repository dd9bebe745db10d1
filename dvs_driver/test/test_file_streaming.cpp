// Streaming file sources and the replay over them: files larger than the replay's queue arrive
// completely and in order (equal to the whole-file readers), the threads stop cleanly in the
// middle of a file, and bad files give errors naming them (at open, or part way through).
#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/event_file.h>
#include <dvs_driver/event_source.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/file_replay.h>
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <string>

using dvs_driver::Event;
using dvs_driver::EventVector;

namespace
{
const std::string kDataDir = DVS_REAL_DATA_DIR;

struct Collect : dvs_driver::EventInputListener
{
  std::mutex mutex;
  std::condition_variable cv;
  EventVector events;
  bool ended = false;
  std::string error;
  void onEvents(const Event* b, const Event* e) override
  {
    std::lock_guard<std::mutex> lock(mutex);
    events.insert(events.end(), b, e);
    cv.notify_all();
  }
  void onEndOfInput() override
  {
    std::lock_guard<std::mutex> lock(mutex);
    ended = true;
    cv.notify_all();
  }
  void onInputError(const std::string& message) override
  {
    std::lock_guard<std::mutex> lock(mutex);
    error = message;
    cv.notify_all();
  }
  template <class Pred>
  bool waitFor(Pred pred)
  {
    std::unique_lock<std::mutex> lock(mutex);
    return cv.wait_for(lock, std::chrono::seconds(60), pred);
  }
};

std::string tempPath(const std::string& name)
{
  return testing::TempDir() + "file_streaming_" + std::to_string(::getpid()) + "_" + name;
}

// n events, 1 us apart from t = 0.5 s, pixels spread over a DAVIS240 (x up to 239).
EventVector makeEvents(size_t n)
{
  EventVector v(n);
  for (size_t i = 0; i < n; ++i)
    v[i] = Event{500000000LL + static_cast<int64_t>(i) * 1000, static_cast<uint16_t>(i * 7 % 240),
                 static_cast<uint16_t>(i * 13 % 180), i % 3 == 0};
  return v;
}

EventVector readAll(dvs_driver::EventSource& s, size_t block)
{
  EventVector out;
  while (s.read(out, block) > 0)
  {
  }
  return out;
}

void expectEqual(const EventVector& want, const EventVector& got)
{
  ASSERT_EQ(want.size(), got.size());
  for (size_t i = 0; i < want.size(); ++i)
    ASSERT_EQ(want[i], got[i]) << i;
}

dvs_driver::FileReplayOptions smallQueue()
{
  dvs_driver::FileReplayOptions o;
  o.speed = 0;  // as fast as possible
  o.read_block = 1000;
  o.queue_events = 5000;
  return o;
}
}  // namespace

TEST(FileStreaming, TextFileLargerThanTheQueueArrivesCompletelyInOrder)
{
  const EventVector ev = makeEvents(200000);
  const std::string path = tempPath("big.txt");
  dvs_driver::writeEventsText(path, ev);
  auto source = dvs_driver::openEventFileSource(path);
  EXPECT_EQ(0u, source->info().width);  // a text file does not say; the probe finds it
  uint32_t w = 0, h = 0;
  std::string sensor;
  const dvs_driver::SourceProbe probe = dvs_driver::probeSource(*source, w, h, sensor);
  EXPECT_EQ(240u, w);
  EXPECT_EQ(180u, h);
  EXPECT_EQ("DAVIS240", sensor);
  EXPECT_FALSE(probe.empty);
  EXPECT_EQ(ev.front().t_ns, probe.first_t_ns);

  const auto o = smallQueue();
  dvs_driver::FileReplay replay(std::move(source), o);
  Collect c;
  replay.start(c);
  ASSERT_TRUE(c.waitFor([&] { return c.ended || !c.error.empty(); }));
  replay.stop();
  EXPECT_EQ("", c.error);
  expectEqual(ev, c.events);
  EXPECT_LE(replay.maxQueued(), o.queue_events);  // never more read ahead than the bound
  EXPECT_GT(replay.maxQueued(), 0u);
  std::remove(path.c_str());
}

TEST(FileStreaming, RealAedatRecordingsEqualTheWholeFileReader)
{
  for (const char* name : {"ucsd_alex_walking_again.aedat", "biolab_dataset2_caixa_negative_ts.aedat",
                           "IMU_rotDisk.aedat", "colleen_pen_short.aedat"})
  {
    SCOPED_TRACE(name);
    const std::string path = kDataDir + "/" + name;
    const dvs_driver::AedatRecording whole = dvs_driver::readAedat(path);
    dvs_driver::AedatFileSource source(path);
    EXPECT_EQ(whole.stream.width, source.info().width);
    EXPECT_EQ(whole.stream.height, source.info().height);
    EXPECT_EQ(whole.info.sensor_name, source.info().sensor_name);
    // Odd block sizes: records split every way across reads.
    expectEqual(whole.stream.events, readAll(source, 777));
    EXPECT_EQ(whole.info.skippedRecords(), source.aedatInfo().skippedRecords());
    EXPECT_EQ(whole.info.timestamp_wraps, source.aedatInfo().timestamp_wraps);
    EXPECT_EQ(whole.info.non_monotonic, source.aedatInfo().non_monotonic);
    source.rewind();  // and again from the start
    expectEqual(whole.stream.events, readAll(source, 4096));

    // Through the replay with a queue far smaller than the file.
    Collect c;
    dvs_driver::FileReplay replay(std::unique_ptr<dvs_driver::EventSource>(new dvs_driver::AedatFileSource(path)),
                                  smallQueue());
    replay.start(c);
    ASSERT_TRUE(c.waitFor([&] { return c.ended || !c.error.empty(); }));
    replay.stop();
    EXPECT_EQ("", c.error);
    expectEqual(whole.stream.events, c.events);
  }
}

TEST(FileStreaming, LoopedFileKeepsTimeIncreasing)
{
  const EventVector ev = makeEvents(3000);
  const std::string path = tempPath("loop.txt");
  dvs_driver::writeEventsText(path, ev);
  auto o = smallQueue();
  o.loop = true;
  dvs_driver::FileReplay replay(dvs_driver::openEventFileSource(path), o);
  Collect c;
  replay.start(c);
  ASSERT_TRUE(c.waitFor([&] { return c.events.size() >= 3 * ev.size(); }));
  replay.stop();
  std::lock_guard<std::mutex> lock(c.mutex);
  for (size_t i = 1; i < c.events.size(); ++i)
    ASSERT_GT(c.events[i].t_ns, c.events[i - 1].t_ns) << i;
  // Each loop starts one span + 1 ms after the previous loop's first event.
  const int64_t step = ev.back().t_ns - ev.front().t_ns + 1000000;
  EXPECT_EQ(ev.front().t_ns + step, c.events[ev.size()].t_ns);
  EXPECT_EQ(ev.front().t_ns + 2 * step, c.events[2 * ev.size()].t_ns);
  EXPECT_FALSE(c.ended);
  std::remove(path.c_str());
}

TEST(FileStreaming, StopsCleanlyInTheMiddleOfAFile)
{
  // 200 000 events over 0.2 s of file time, replayed at 1/1000 of real time: 200 s to play,
  // so the destruction below happens in the middle, with the reader blocked on a full queue.
  const EventVector ev = makeEvents(200000);
  const std::string path = tempPath("long.txt");
  dvs_driver::writeEventsText(path, ev);
  auto o = smallQueue();
  o.speed = 0.001;
  Collect c;
  const auto t0 = std::chrono::steady_clock::now();
  {
    dvs_driver::FileReplay replay(dvs_driver::openEventFileSource(path), o);
    replay.start(c);
    ASSERT_TRUE(c.waitFor([&] { return !c.events.empty(); }));
  }  // destructor: stops and joins both threads
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 30.0);  // far from the 200 s the whole file would take
  std::lock_guard<std::mutex> lock(c.mutex);
  EXPECT_LT(c.events.size(), ev.size());
  EXPECT_FALSE(c.ended);
  for (size_t i = 0; i < c.events.size(); ++i)
    ASSERT_EQ(ev[i], c.events[i]) << i;
  std::remove(path.c_str());
}

TEST(FileStreaming, UnreadableFilesGiveErrorsNamingThem)
{
  auto errorOf = [](const std::string& path) {
    try
    {
      dvs_driver::openEventFileSource(path);
    }
    catch (const dvs_driver::EventFileError& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  for (const std::string path : {"/nonexistent/rec.aedat", "/nonexistent/events.txt"})
  {
    const std::string err = errorOf(path);
    EXPECT_NE(std::string::npos, err.find(path)) << err;
    EXPECT_NE(std::string::npos, err.find("No such file")) << err;
  }
  const std::string dir = testing::TempDir();
  EXPECT_NE(std::string::npos, errorOf(dir).find("is a directory")) << errorOf(dir);
  const std::string not_aedat = tempPath("not.aedat");
  std::ofstream(not_aedat) << "hello\n";
  const std::string err = errorOf(not_aedat);
  EXPECT_NE(std::string::npos, err.find(not_aedat)) << err;
  EXPECT_NE(std::string::npos, err.find("not an AEDAT file")) << err;
  EXPECT_NE(std::string::npos, errorOf("x.bag").find("BagEventSource"));
  std::remove(not_aedat.c_str());
}

TEST(FileStreaming, MalformedLinePartWayThroughIsReportedAfterTheEventsBeforeIt)
{
  const EventVector ev = makeEvents(12500);  // the fault in the middle of a read block
  const std::string path = tempPath("bad.txt");
  {
    std::ofstream out(path);
    dvs_driver::writeEventsText(out, ev);
    out << "0.9 1 2 7\n";  // line 12501: bad polarity
  }
  dvs_driver::FileReplay replay(dvs_driver::openEventFileSource(path), smallQueue());
  Collect c;
  replay.start(c);
  ASSERT_TRUE(c.waitFor([&] { return c.ended || !c.error.empty(); }));
  replay.stop();
  EXPECT_FALSE(c.ended);
  EXPECT_NE(std::string::npos, c.error.find(path + ":12501: polarity")) << c.error;
  expectEqual(ev, c.events);
  std::remove(path.c_str());
}
