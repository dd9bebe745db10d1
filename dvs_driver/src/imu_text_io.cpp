#include <dvs_driver/checked_write.h>
#include <dvs_driver/imu_text_io.h>

#include <cerrno>
#include <charconv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace dvs_driver
{
const char* const kImuTextHeader = "# t ax ay az gx gy gz (s, m/s^2, rad/s)\n";

namespace
{
bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r'; }

[[noreturn]] void fail(const std::string& name, size_t line, const std::string& what)
{
  throw EventFileError(name + ":" + std::to_string(line) + ": " + what);
}

const char* const kFieldNames[7] = {"t", "ax", "ay", "az", "gx", "gy", "gz"};

// One imu.txt line: false for a blank or comment line, else the sample. Throws naming `name`
// and the line on malformed lines, non-finite values and times going back from `last_t`.
bool parseImuLine(const std::string& line, const std::string& name, size_t line_no, int64_t& last_t, ImuSample& s)
{
  const char* p = line.data();
  const char* end = p + line.size();
  while (p < end && isSpace(*p))
    ++p;
  if (p == end || *p == '#')
    return false;
  const char* tok[7];
  const char* tok_end[7];
  for (int i = 0; i < 7; ++i)
  {
    while (p < end && isSpace(*p))
      ++p;
    if (p == end)
      fail(name, line_no, "expected 7 fields `t ax ay az gx gy gz`, got " + std::to_string(i));
    tok[i] = p;
    while (p < end && !isSpace(*p))
      ++p;
    tok_end[i] = p;
  }
  while (p < end && isSpace(*p))
    ++p;
  if (p != end)
    fail(name, line_no, "more than 7 fields (expected `t ax ay az gx gy gz`)");
  if (!parseSecondsToNs(tok[0], tok_end[0], s.t_ns))
    fail(name, line_no, "time `" + std::string(tok[0], tok_end[0]) + "` is not a number of seconds");
  for (int i = 1; i < 7; ++i)
  {
    double v = 0;
    const char* b = tok[i];
    if (b < tok_end[i] && *b == '+')
      ++b;  // from_chars takes no '+'
    const auto r = std::from_chars(b, tok_end[i], v);
    const std::string text(tok[i], tok_end[i]);
    if (r.ec == std::errc::result_out_of_range)
      fail(name, line_no, std::string(kFieldNames[i]) + " `" + text + "` is out of range");
    if (r.ec != std::errc() || r.ptr != tok_end[i])
      fail(name, line_no, std::string(kFieldNames[i]) + " `" + text + "` is not a number");
    if (!std::isfinite(v))
      fail(name, line_no, std::string(kFieldNames[i]) + " `" + text + "` is not finite");
    (i <= 3 ? s.accel[i - 1] : s.gyro[i - 4]) = v;
  }
  if (s.t_ns < last_t)
    fail(name, line_no, "time goes backwards (imu.txt must be sorted by time)");
  last_t = s.t_ns;
  s.temperature_c = NAN;
  return true;
}

// The line of one sample into buf (no newline); returns its length.
size_t formatSample(const ImuSample& s, char* buf, size_t size)
{
  const int64_t a = s.t_ns < 0 ? -s.t_ns : s.t_ns;
  int n = std::snprintf(buf, size, "%s%" PRId64 ".%09" PRId64, s.t_ns < 0 ? "-" : "",
                        static_cast<int64_t>(a / 1000000000), static_cast<int64_t>(a % 1000000000));
  char* p = buf + n;
  char* const e = buf + size;
  for (int i = 0; i < 6; ++i)
  {
    const double v = i < 3 ? s.accel[i] : s.gyro[i - 3];
    *p++ = ' ';
    const auto r = std::to_chars(p, e, v);  // shortest form that reads back exactly
    p = r.ptr;
  }
  return static_cast<size_t>(p - buf);
}

void checkFinite(const ImuSample& s, size_t index)
{
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(s.accel[i]) || !std::isfinite(s.gyro[i]))
      throw EventFileError("IMU sample " + std::to_string(index) + " has a non-finite value: imu.txt cannot hold it");
}
}  // namespace

ImuVector readImuText(std::istream& in, const std::string& name)
{
  ImuVector samples;
  std::string line;
  size_t line_no = 0;
  int64_t last_t = INT64_MIN;
  ImuSample s;
  while (std::getline(in, line))
    if (parseImuLine(line, name, ++line_no, last_t, s))
      samples.push_back(s);
  if (in.bad())
    throw EventFileError(name + ": read error");
  return samples;
}

ImuVector readImuText(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw EventFileError(path + ": cannot open IMU file: " + std::strerror(errno));
  return readImuText(in, path);
}

std::string formatImuLine(const ImuSample& s)
{
  char buf[256];
  return std::string(buf, formatSample(s, buf, sizeof(buf)));
}

void writeImuText(std::ostream& out, const ImuVector& samples, const char* header)
{
  out << header;
  char buf[256];
  for (size_t i = 0; i < samples.size(); ++i)
  {
    checkFinite(samples[i], i);
    const size_t n = formatSample(samples[i], buf, sizeof(buf) - 1);
    buf[n] = '\n';
    out.write(buf, static_cast<std::streamsize>(n + 1));
  }
}

void writeImuText(const std::string& path, const ImuVector& samples, const char* header)
{
  CheckedFileWriter out(path);  // throws WriteError naming the file and the reason
  writeImuText(out.stream(), samples, header);
  out.commit();
}
}  // namespace dvs_driver
