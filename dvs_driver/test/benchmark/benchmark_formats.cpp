// rosrun dvs_driver benchmark_formats FILE...  (default: the known-answer samples)
// Decoding speed of the streaming format readers: each run opens the file and reads every event
// (file in the page cache) 20 times, in batches of 65,536 events into a reused vector; prints the
// median of 5 runs in M events/s of this thread's CPU time (the one-core figure; wall-clock time
// on a shared machine counts other processes' time too, so it is printed alongside). For
// AEDAT 4.0 the figure includes LZ4 / zstd decompression; each AEDAT 4.0 input is also timed as
// an uncompressed copy (written to /tmp by Aedat4Writer, removed afterwards): the decoding
// without decompression, and its event packets' LZ4 / zstd decompression alone (formats::Decompressor
// into a reused buffer, the reader's own path): the ceiling of the compressed figure on this machine.
#include <dvs_driver/formats/aedat4.h>
#include <dvs_driver/formats/compression.h>
#include <dvs_driver/formats/event_format.h>
#include <dvs_driver/formats/flatbuffer_view.h>

#include <fstream>
#include <iterator>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <unistd.h>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

using namespace dvs_driver;

namespace
{
double threadCpuSeconds()
{
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/// Returns CPU seconds; wall seconds in `wall`.
double decodeOnce(const std::string& path, size_t repeats, uint64_t& events, std::string& name, double& wall)
{
  const double c0 = threadCpuSeconds();
  EventVector batch;
  batch.reserve(1 << 17);
  const auto t0 = std::chrono::steady_clock::now();
  events = 0;
  for (size_t r = 0; r < repeats; ++r)
  {
    auto reader = openEventFileReader(path);
    name = reader->formatName();
    for (;;)
    {
      batch.clear();
      if (!reader->read(batch, 1 << 16))
        break;
      events += batch.size();
    }
  }
  const auto t1 = std::chrono::steady_clock::now();
  wall = std::chrono::duration<double>(t1 - t0).count();
  return threadCpuSeconds() - c0;
}
/// The compressed payloads of stream `stream`'s packets of an AEDAT 4.0 file (packets scanned
/// from the IOHeader to the data table); compression from the IOHeader (0 none, 1-2 LZ4, 3-4 zstd).
std::vector<std::vector<uint8_t>> aedat4Payloads(const std::string& path, int32_t stream, int32_t& compression)
{
  std::ifstream in(path, std::ios::binary);
  const std::vector<uint8_t> d((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::vector<uint8_t>> out;
  if (d.size() < 18)
    return out;
  const uint32_t n = formats::loadLE<uint32_t>(d.data() + 14);
  if (18 + uint64_t(n) > d.size())
    return out;
  const formats::FlatTable io = formats::FlatTable::root(d.data() + 18, n);
  compression = io.scalar<int32_t>(0, 0);
  const int64_t table = io.scalar<int64_t>(1, -1);
  const uint64_t end = table > 0 ? uint64_t(table) : d.size();
  for (uint64_t pos = 18 + uint64_t(n); pos + 8 <= end;)
  {
    const int32_t id = formats::loadLE<int32_t>(d.data() + pos), size = formats::loadLE<int32_t>(d.data() + pos + 4);
    if (size < 0 || pos + 8 + uint64_t(size) > end)
      break;
    if (id == stream)
      out.emplace_back(d.begin() + long(pos + 8), d.begin() + long(pos + 8 + uint64_t(size)));
    pos += 8 + uint64_t(size);
  }
  return out;
}
}  // namespace

int main(int argc, char** argv)
{
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i)
    files.push_back(argv[i]);
#ifdef DVS_FORMATS_DATA_DIR
  if (files.empty())
    for (const char* f : {"prophesee_evt3_gen41_1280x720.raw", "prophesee_evt2_gen3_640x480.raw",
                          "dvxplorer_320x240.aedat4", "davis346_346x260.aedat4"})
      files.push_back(std::string(DVS_FORMATS_DATA_DIR) + "/" + f);
#endif
  if (files.empty())
  {
    std::fprintf(stderr, "usage: benchmark_formats FILE...\n");
    return 2;
  }
  auto bench = [](const std::string& path, const std::string& label) {
    std::vector<double> rates, wall_rates;
    uint64_t events = 0;
    std::string name;
    double wall = 0;
    decodeOnce(path, 2, events, name, wall);  // warm the page cache
    for (int run = 0; run < 5; ++run)
    {
      const double s = decodeOnce(path, 20, events, name, wall);
      rates.push_back(events / s / 1e6);
      wall_rates.push_back(events / wall / 1e6);
    }
    std::sort(rates.begin(), rates.end());
    std::sort(wall_rates.begin(), wall_rates.end());
    std::printf("%-48s %-26s %8llu events  %6.1f M events/s CPU (median of 5; min %.1f, max %.1f)  "
                "%6.1f M events/s wall\n",
                label.c_str(), name.c_str(), static_cast<unsigned long long>(events / 20), rates[2], rates[0],
                rates[4], wall_rates[2]);
  };
  for (const auto& path : files)
  {
    try
    {
      const std::string label = path.substr(path.find_last_of('/') + 1);
      bench(path, label);
      if (detectEventFormat(path) == EventFormat::Aedat4)
      {
        auto in = openEventFileReader(path);
        const EventVector all = in->readAll();
        const std::string copy = "/tmp/benchmark_formats_" + std::to_string(::getpid()) + ".aedat4";
        formats::Aedat4WriterOptions o;
        o.compression = formats::Aedat4Compression::None;
        {
          formats::Aedat4Writer w(copy, in->width(), in->height(), o);
          w.write(all);
          w.close();
        }
        bench(copy, label + " (uncompressed)");
        std::remove(copy.c_str());
        // The decompression alone (stream 0, the event stream of DV's files).
        int32_t compression = 0;
        const auto payloads = aedat4Payloads(path, 0, compression);
        if (compression >= 1 && compression <= 4 && !payloads.empty())
        {
          formats::Decompressor dec;
          formats::ByteBuffer raw;
          std::vector<double> rates;
          for (int run = 0; run < 5; ++run)
          {
            const double c0 = threadCpuSeconds();
            for (int r = 0; r < 20; ++r)
              for (const auto& p : payloads)
              {
                const std::string err = compression <= 2 ? dec.lz4(p.data(), p.size(), raw) : dec.zstd(p.data(), p.size(), raw);
                if (!err.empty())
                  throw std::runtime_error(path + ": " + err);
              }
            rates.push_back(20.0 * double(all.size()) / (threadCpuSeconds() - c0) / 1e6);
          }
          std::sort(rates.begin(), rates.end());
          std::printf("%-48s %-26s %8zu events  %6.1f M events/s CPU (median of 5; min %.1f, max %.1f)\n",
                      (label + " (decompression alone)").c_str(), compression <= 2 ? "LZ4 frames" : "zstd frames",
                      all.size(), rates[2], rates[0], rates[4]);
        }
      }
    }
    catch (const std::exception& e)
    {
      std::fprintf(stderr, "%s\n", e.what());
      return 1;
    }
  }
  return 0;
}
