#include <dvs_driver/checked_write.h>
#include <dvs_driver/event_text_io.h>

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace dvs_driver
{
namespace
{
const char* skipSpace(const char* p, const char* end)
{
  while (p < end && (*p == ' ' || *p == '\t' || *p == '\r'))
    ++p;
  return p;
}

const char* tokenEnd(const char* p, const char* end)
{
  while (p < end && *p != ' ' && *p != '\t' && *p != '\r')
    ++p;
  return p;
}

/// Skips a leading sign; true when it was '-'.
bool takeSign(const char*& b, const char* e)
{
  const bool neg = b < e && *b == '-';
  if (b < e && (*b == '-' || *b == '+'))
    ++b;
  return neg;
}

bool parseInt(const char* b, const char* e, long& v)
{
  const bool neg = takeSign(b, e);
  if (b == e)
    return false;
  long r = 0;
  for (; b < e; ++b)
  {
    if (*b < '0' || *b > '9' || r > 100000000L)
      return false;
    r = r * 10 + (*b - '0');
  }
  v = neg ? -r : r;
  return true;
}

[[noreturn]] void fail(const std::string& name, size_t line, const std::string& what)
{
  throw EventFileError(name + ":" + std::to_string(line) + ": " + what);
}
}  // namespace

bool parseSecondsToNs(const char* b, const char* e, int64_t& ns)
{
  if (b == e)
    return false;
  const bool neg = takeSign(b, e);
  int64_t whole = 0;
  int digits = 0;
  for (; b < e && *b >= '0' && *b <= '9'; ++b, ++digits)
  {
    whole = whole * 10 + (*b - '0');
    if (whole > 9000000000LL)  // > ~285 years: not a time stamp (and ns would overflow int64)
      return false;
  }
  int64_t frac = 0;
  int frac_digits = 0;
  if (b < e && *b == '.')
  {
    ++b;
    for (; b < e && *b >= '0' && *b <= '9'; ++b)
    {
      if (frac_digits < 9)
      {
        frac = frac * 10 + (*b - '0');
        ++frac_digits;
      }
      ++digits;
    }
  }
  if (b != e || digits == 0)
    return false;
  for (int i = frac_digits; i < 9; ++i)
    frac *= 10;
  ns = whole * 1000000000LL + frac;
  if (neg)
    ns = -ns;
  return true;
}

// One line of events.txt: false for a blank or comment line, else the event. Throws naming
// `name` and the line on malformed lines and on times that go backwards from `last_t`.
bool parseEventLine(const std::string& line, const std::string& name, size_t line_no, int64_t& last_t, Event& ev)
{
  const char* p = line.data();
  const char* end = p + line.size();
  p = skipSpace(p, end);
  if (p == end || *p == '#')
    return false;
  const char* tok[4];
  const char* tok_end[4];
  for (int i = 0; i < 4; ++i)
  {
    p = skipSpace(p, end);
    if (p == end)
      fail(name, line_no, "expected 4 fields `t x y p`, got " + std::to_string(i));
    tok[i] = p;
    p = tokenEnd(p, end);
    tok_end[i] = p;
  }
  if (skipSpace(p, end) != end)
    fail(name, line_no, "more than 4 fields (expected `t x y p`)");
  if (!parseSecondsToNs(tok[0], tok_end[0], ev.t_ns))
    fail(name, line_no, "time `" + std::string(tok[0], tok_end[0]) + "` is not a number of seconds");
  long x, y, pol;
  if (!parseInt(tok[1], tok_end[1], x) || !parseInt(tok[2], tok_end[2], y))
    fail(name, line_no, "pixel coordinates must be integers");
  if (x < 0 || y < 0 || x > 65535 || y > 65535)
    fail(name, line_no, "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") out of range");
  if (!parseInt(tok[3], tok_end[3], pol) || (pol != 0 && pol != 1))
    fail(name, line_no, "polarity must be 0 or 1");
  if (ev.t_ns < last_t)
    fail(name, line_no, "time goes backwards (events.txt must be sorted by time)");
  last_t = ev.t_ns;
  ev.x = static_cast<uint16_t>(x);
  ev.y = static_cast<uint16_t>(y);
  ev.polarity = pol == 1;
  return true;
}

EventVector readEventsText(std::istream& in, const std::string& name)
{
  return readEventsText(in, name, ReadProgress(), 0);
}

EventVector readEventsText(std::istream& in, const std::string& name, const ReadProgress& progress,
                           uint64_t total_bytes)
{
  EventVector events;
  std::string line;
  size_t line_no = 0;
  uint64_t bytes = 0;
  int64_t last_t = INT64_MIN;
  Event ev;
  while (std::getline(in, line))
  {
    if (parseEventLine(line, name, ++line_no, last_t, ev))
      events.push_back(ev);
    bytes += line.size() + 1;
    if (progress && (line_no & 0xFFFF) == 0)
      progress(events.size(), bytes, total_bytes);
  }
  if (in.bad())
    throw EventFileError(name + ": read error");
  return events;
}

EventVector readEventsText(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw EventFileError(path + ": cannot open events file: " + std::strerror(errno));
  return readEventsText(in, path);
}

TextFileSource::TextFileSource(const std::string& path) : in_(path)
{
  info_.name = path;
  info_.format = "events.txt";
  if (!in_)
    throw EventFileError(path + ": cannot open events file: " + std::strerror(errno));
}

size_t TextFileSource::read(EventVector& out, size_t max_events)
{
  size_t n = 0;
  Event ev;
  while (n < max_events && std::getline(in_, line_))
    if (parseEventLine(line_, info_.name, ++line_no_, last_t_, ev))
    {
      out.push_back(ev);
      ++n;
    }
  if (in_.bad())
    throw EventFileError(info_.name + ": read error");
  return n;
}

void TextFileSource::rewind()
{
  in_.clear();
  in_.seekg(0);
  line_no_ = 0;
  last_t_ = INT64_MIN;
}

namespace
{
// The line of one event into buf (no newline); returns its length.
int formatEvent(const Event& e, char* buf, size_t size)
{
  const int64_t a = e.t_ns < 0 ? -e.t_ns : e.t_ns;
  return std::snprintf(buf, size, "%s%" PRId64 ".%09" PRId64 " %u %u %d", e.t_ns < 0 ? "-" : "",
                       static_cast<int64_t>(a / 1000000000), static_cast<int64_t>(a % 1000000000), e.x, e.y,
                       e.polarity ? 1 : 0);
}
}  // namespace

std::string formatEventLine(const Event& e)
{
  char buf[64];
  formatEvent(e, buf, sizeof(buf));
  return buf;
}

void writeEventsText(std::ostream& out, const EventVector& events, const WriteProgress& progress)
{
  char buf[64];
  for (size_t i = 0; i < events.size(); ++i)
  {
    const int n = formatEvent(events[i], buf, sizeof(buf) - 1);
    buf[n] = '\n';
    out.write(buf, n + 1);
    if (progress && (i & 0xFFFF) == 0xFFFF)
      progress(i + 1);
  }
  if (progress)
    progress(events.size());
}

void writeEventsText(const std::string& path, const EventVector& events, const WriteProgress& progress)
{
  CheckedFileWriter out(path);  // throws WriteError naming the file and the reason
  writeEventsText(out.stream(), events, progress);
  out.commit();
}
}  // namespace dvs_driver
