#pragma once
// Helpers of the format-reader tests: the known-answer sample directory, temporary files,
// summaries of decoded events.
#include <dvs_driver/formats/event_format.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

namespace formats_test
{
using dvs_driver::Event;
using dvs_driver::EventVector;

inline std::string sample(const std::string& name)
{
  return std::string(DVS_FORMATS_DATA_DIR) + "/" + name;
}

inline std::vector<uint8_t> readBytes(const std::string& path)
{
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

/// A file in /tmp removed at the end of the test.
class TempFile
{
public:
  explicit TempFile(const std::string& suffix)
  {
    static int counter = 0;
    path_ = "/tmp/dvs_formats_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + suffix;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }
  void write(const std::vector<uint8_t>& bytes) const { write(bytes.data(), bytes.size()); }
  void write(const uint8_t* data, size_t n) const
  {
    std::ofstream f(path_, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(n));
  }

private:
  std::string path_;
};

struct Summary
{
  size_t n = 0, on = 0;
  int min_x = 1 << 30, max_x = -1, min_y = 1 << 30, max_y = -1;
};

inline Summary summarize(const EventVector& ev)
{
  Summary s;
  s.n = ev.size();
  for (const Event& e : ev)
  {
    s.on += e.polarity;
    s.min_x = std::min<int>(s.min_x, e.x);
    s.max_x = std::max<int>(s.max_x, e.x);
    s.min_y = std::min<int>(s.min_y, e.y);
    s.max_y = std::max<int>(s.max_y, e.y);
  }
  return s;
}

/// Event from the samples README notation (x, y, t_us, p).
inline Event ev(int x, int y, int64_t t_us, int p)
{
  return Event{t_us * 1000, uint16_t(x), uint16_t(y), p != 0};
}

/// Read through the streaming interface with a given batch size.
inline EventVector readInBatches(dvs_driver::EventFileReader& r, size_t batch)
{
  EventVector all, part;
  while (true)
  {
    part.clear();
    if (!r.read(part, batch))
      break;
    EXPECT_LE(part.size(), batch);
    all.insert(all.end(), part.begin(), part.end());
  }
  return all;
}
}  // namespace formats_test
