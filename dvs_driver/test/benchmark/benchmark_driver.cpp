// benchmark_driver: the figures of dvs_driver's BENCHMARKS.md.
//
//   rosrun dvs_driver benchmark_driver decode [--events N] [--runs R]
//       Decoding speed of the DVS128 word decoder on one core (no ROS, no USB).
//   rosrun dvs_driver benchmark_driver latency [--rate EV_PER_S] [--seconds S] [--period-ms P]
//       Needs a ROS master (roscore). An emulated DVS128 (umockdev, real libusb path) streams at
//       the rate; the driver nodelet is loaded in this process and an in-process subscriber
//       measures, per packet, the time from the completion of the USB transfer holding its last
//       event to the packet's delivery; counts lost or reordered events.
#include "emulator/dvs128_emulator.h"

#include <dvs_driver/command_line.h>
#include <dvs_driver/dvs128_decoder.h>
#include <dvs_driver/event_bag_io.h>

#include <dvs_msgs/EventArray.h>
#include <nodelet/loader.h>
#include <ros/ros.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <random>
#include <thread>
#include <string>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;

double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

double percentile(std::vector<double> v, double p)
{
  if (v.empty())
    return 0.0;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(p / 100.0 * static_cast<double>(v.size())));
  return v[i];
}

// Realistic stream: pixel events with increasing 16-bit time, a wrap every 16384 us.
std::vector<uint8_t> makeWords(size_t events)
{
  std::vector<uint8_t> b;
  b.reserve(events * 4 + events / 100 * 4);
  std::mt19937 rng(1);
  uint32_t t = 0;
  for (size_t i = 0; i < events; ++i)
  {
    t += rng() % 2;  // ~2 events per us
    if (t >= 16384)
    {
      t -= 16384;
      b.insert(b.end(), {0, 0, 0, 0x80});
    }
    const uint16_t addr = static_cast<uint16_t>(rng() & 0x7FFF);
    b.insert(b.end(), {static_cast<uint8_t>(addr), static_cast<uint8_t>(addr >> 8), static_cast<uint8_t>(t),
                       static_cast<uint8_t>(t >> 8)});
  }
  return b;
}

struct SumConsumer : dvs_driver::Dvs128ConsumerBase
{
  uint64_t sum = 0;
  void event(int64_t t, uint16_t x, uint16_t y, bool p) { sum += static_cast<uint64_t>(t) + x + y + p; }
};

struct VectorConsumer : dvs_driver::Dvs128ConsumerBase
{
  dvs_driver::Event* out;
  void event(int64_t t, uint16_t x, uint16_t y, bool p) { *out++ = dvs_driver::Event{t * 1000, x, y, p}; }
};

int decodeBenchmark(size_t events, int runs)
{
  const std::vector<uint8_t> words = makeWords(events);
  dvs_driver::EventVector out(events);
  std::vector<double> sum_rates, vec_rates, msg_rates;
  uint64_t check = 0;
  for (int r = 0; r < runs; ++r)
  {
    {
      dvs_driver::Dvs128Decoder d;
      SumConsumer c;
      const auto t0 = Clock::now();
      for (size_t off = 0; off < words.size(); off += 4096)  // 4 KiB transfers
        d.decode(words.data() + off, std::min<size_t>(4096, words.size() - off), c);
      const double s = std::chrono::duration<double>(Clock::now() - t0).count();
      sum_rates.push_back(static_cast<double>(d.stats().events) / s);
      check += c.sum;
    }
    {
      dvs_driver::Dvs128Decoder d;
      VectorConsumer c;
      c.out = out.data();
      const auto t0 = Clock::now();
      for (size_t off = 0; off < words.size(); off += 4096)
        d.decode(words.data() + off, std::min<size_t>(4096, words.size() - off), c);
      const double s = std::chrono::duration<double>(Clock::now() - t0).count();
      vec_rates.push_back(static_cast<double>(d.stats().events) / s);
      check += out[events / 2].x;
    }
    {
      // The driver's path: decode a transfer into a reused chunk, append it to an EventArray
      // (1 ms packets at ~2 events/us: ~2000 events each, buffer reserved and reused).
            dvs_driver::Dvs128Decoder d;
      dvs_driver::EventVector chunk(2048);
      dvs_msgs::EventArray msg;
      msg.events.reserve(4096);
      uint64_t packets = 0;
      const auto t0 = Clock::now();
      for (size_t off = 0; off < words.size(); off += 4096)
      {
        VectorConsumer c;
        c.out = chunk.data();
        d.decode(words.data() + off, std::min<size_t>(4096, words.size() - off), c);
        dvs_driver::appendToMessage(chunk.data(), c.out, msg);
        if (msg.events.size() >= 2000)
        {
          check += msg.events.back().x;
          msg.events.clear();
          ++packets;
        }
      }
      const double s = std::chrono::duration<double>(Clock::now() - t0).count();
      msg_rates.push_back(static_cast<double>(d.stats().events) / s);
      check += packets;
    }
  }
  std::printf("decode: %zu events in 4 KiB transfers, %d runs (checksum %llu)\n", events, runs,
              static_cast<unsigned long long>(check));
  std::printf("  into an inlined consumer (no store): median %.1f M events/s\n", median(sum_rates) * 1e-6);
  std::printf("  into dvs_driver::Event array       : median %.1f M events/s\n", median(vec_rates) * 1e-6);
  std::printf("  into dvs_msgs::EventArray packets  : median %.1f M events/s\n", median(msg_rates) * 1e-6);
  return 0;
}

struct LatencySubscriber
{
  std::mutex mutex;
  uint64_t events = 0, mismatches = 0, packets = 0;
  std::vector<std::pair<uint64_t, Clock::time_point>> arrivals;  // (events so far, time)
  void callback(const dvs_msgs::EventArrayConstPtr& msg)
  {
    const Clock::time_point now = Clock::now();
    std::lock_guard<std::mutex> lock(mutex);
    for (const auto& e : msg->events)
    {
      uint16_t x, y;
      bool p;
      dvs_driver::decodeDvs128Address(dvs_driver_test::generatedAddress(events), x, y, p);
      mismatches += (e.x != x || e.y != y || e.polarity != p);
      ++events;
    }
    ++packets;
    arrivals.emplace_back(events, now);
  }
};

int latencyBenchmark(int argc, char** argv, double rate, double seconds, double period_ms, int transfer_size)
{
  dvs_driver_test::Dvs128Emulator emu("BENCH001", 14);
  emu.setEventRate(rate);
  emu.setFlushIntervalUs(250);
  ros::init(argc, argv, "benchmark_driver", ros::init_options::AnonymousName);
  if (!ros::master::check())
  {
    std::fprintf(stderr, "benchmark_driver latency: no ROS master; start `roscore` first\n");
    return 2;
  }
  const std::string ns = ros::this_node::getName();
  ros::param::set(ns + "_driver/packet_period", period_ms * 1e-3);
  ros::param::set(ns + "_driver/transfer_size", transfer_size);
  ros::param::set(ns + "_driver/serial_number", std::string("BENCH001"));
  ros::AsyncSpinner spinner(2);
  spinner.start();
  LatencySubscriber sub;
  ros::NodeHandle nh(ns + "_driver_ns");
  nodelet::Loader loader(false);
  nodelet::M_string remap;
  remap[ros::names::resolve("/dvs/events")] = nh.resolveName("dvs/events");
  ros::Subscriber s = nh.subscribe<dvs_msgs::EventArray>(
      "dvs/events", 100000, [&sub](const dvs_msgs::EventArrayConstPtr& m) { sub.callback(m); },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  // Load the nodelet with its topics in our namespace so runs do not collide.
  if (!loader.load(ns + "_driver", "dvs_driver/DriverNodelet", remap, nodelet::V_string()))
  {
    std::fprintf(stderr, "cannot load dvs_driver/DriverNodelet\n");
    return 1;
  }
  // Wait for streaming, then measure a window.
  const auto start = Clock::now();
  while (emu.eventsSent() == 0 && Clock::now() - start < std::chrono::seconds(10))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  emu.recordCompletions(true);
  uint64_t first_event;
  {
    std::lock_guard<std::mutex> lock(sub.mutex);
    first_event = sub.events;
    sub.arrivals.clear();
  }
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  emu.setEventLimit(emu.eventsSent());  // stop generating, let everything drain
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  loader.unload(ns + "_driver");
  const auto completions = emu.completions();
  std::lock_guard<std::mutex> lock(sub.mutex);
  // Latency of each packet: arrival - completion of the first URB that contained its last event.
  std::vector<double> lat_ms;
  size_t ci = 0;
  for (const auto& a : sub.arrivals)
  {
    while (ci < completions.size() && completions[ci].events_end < a.first)
      ++ci;
    if (ci == completions.size())
      break;
    if (a.first <= first_event)
      continue;
    lat_ms.push_back(std::chrono::duration<double, std::milli>(a.second - completions[ci].time).count());
  }
  const uint64_t sent = emu.eventsSent();
  std::printf("latency: emulated DVS128 at %.0f events/s for %.1f s, %.1f ms packets, %d-byte transfers\n", rate,
              seconds, period_ms, transfer_size);
  std::printf("  events sent %llu, received %llu, lost %lld, out of order %llu, packets %llu\n",
              static_cast<unsigned long long>(sent), static_cast<unsigned long long>(sub.events),
              static_cast<long long>(sent) - static_cast<long long>(sub.events),
              static_cast<unsigned long long>(sub.mismatches), static_cast<unsigned long long>(sub.packets));
  std::printf("  transfer completion -> subscriber delivery over %zu packets: p50 %.3f ms, p90 %.3f ms, p99 %.3f ms, "
              "max %.3f ms\n",
              lat_ms.size(), percentile(lat_ms, 50), percentile(lat_ms, 90), percentile(lat_ms, 99),
              percentile(lat_ms, 100));
  return 0;
}
}  // namespace

int main(int argc, char** argv)
{
  const std::string mode = argc > 1 ? argv[1] : "";
  double rate = 2e6, seconds = 5.0, period_ms = 1.0, events_d = 20000000;
  int transfer_size = 4096;
  int runs = 5;
  // Options checked by name and range (dvs_driver::parseCommandLine over a ParamTable).
  dvs_driver::ParamTable t("benchmark_driver");
  t.add("--rate", rate, "events/s", 1, 1e8, "latency: generated event rate");
  t.add("--seconds", seconds, "s", 0.1, 3600, "latency: duration");
  t.add("--period-ms", period_ms, "ms", 0.01, 1000, "latency: packet period");
  t.add("--transfer-size", transfer_size, "bytes", 512, 262144, "latency: bulk transfer size");
  t.add("--events", events_d, "events", 1000, 5e7, "decode: events (about 20 bytes of memory each)");
  t.add("--runs", runs, "", 1, 1000, "decode: repetitions");
  const char* usage =
      "usage: benchmark_driver decode [--events N] [--runs R]\n"
      "       benchmark_driver latency [--rate EV_PER_S] [--seconds S] [--period-ms P] [--transfer-size B]\n";
  try
  {
    if (argc < 2 || dvs_driver::parseCommandLine(t, argc - 1, argv + 1))
    {
      std::fprintf(stderr, "%s", usage);
      return 2;
    }
  }
  catch (const dvs_driver::UsageError& e)
  {
    std::fprintf(stderr, "%s\n%s", e.what(), usage);
    return 2;
  }
  const size_t events = static_cast<size_t>(events_d);
  if (mode == "decode")
    return decodeBenchmark(events, runs);
  if (mode == "latency")
  {
    dvs_driver_test::reexecUnderUmockdev(argc, argv);
    return latencyBenchmark(argc, argv, rate, seconds, period_ms, transfer_size);
  }
  std::fprintf(stderr, "%s", usage);
  return 2;
}
