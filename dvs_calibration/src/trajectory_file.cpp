#include <dvs_calibration/trajectory_file.h>
#include <dvs_driver/checked_write.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace dvs_calibration
{
namespace
{
bool parseNumbers(const std::string& line, double* values, int& count)
{
  // Accept whitespace and commas as separators.
  count = 0;
  const char* s = line.c_str();
  while (*s)
  {
    while (*s == ' ' || *s == '\t' || *s == ',' || *s == '\r')
      ++s;
    if (!*s)
      break;
    char* end = nullptr;
    const double v = std::strtod(s, &end);
    if (end == s)
      return false;
    if (count < 8)
      values[count] = v;
    ++count;
    s = end;
  }
  return true;
}
}  // namespace

Trajectory readTumTrajectory(std::istream& in, const std::string& name, TimeOrder order)
{
  Trajectory poses;
  std::string line;
  int line_no = 0;
  bool first_content_line = true;
  while (std::getline(in, line))
  {
    ++line_no;
    size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#')
      continue;
    double v[8];
    int count = 0;
    const bool numeric = parseNumbers(line, v, count);
    if (!numeric && first_content_line && line.find(',') != std::string::npos)
    {
      first_content_line = false;  // CSV header line
      continue;
    }
    first_content_line = false;
    const std::string where = name + ":" + std::to_string(line_no) + ": ";
    if (!numeric)
      throw TrajectoryFileError(where + "not a number in '" + line + "'");
    if (count != 8)
      throw TrajectoryFileError(where + "expected 8 values 't tx ty tz qx qy qz qw', got " + std::to_string(count));
    for (double x : v)
      if (!std::isfinite(x))
        throw TrajectoryFileError(where + "non-finite value");
    StampedPose sp;
    sp.t = v[0];
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    const double n = q.norm();
    if (n < 0.5 || n > 1.5)
      throw TrajectoryFileError(where + "quaternion norm " + std::to_string(n) + " is far from 1");
    sp.T_world_camera = Pose::fromWorldCamera(q.normalized(), Eigen::Vector3d(v[1], v[2], v[3]));
    const bool in_order = poses.empty() || sp.t > poses.back().t ||
                          (order == TimeOrder::NonDecreasing && sp.t == poses.back().t);
    if (!in_order)
      throw TrajectoryFileError(where + "time " + std::to_string(sp.t) +
                                (order == TimeOrder::NonDecreasing ? " goes backwards" : " does not increase") +
                                " (previous " + std::to_string(poses.back().t) + ")");
    poses.push_back(sp);
  }
  return poses;
}

Trajectory readTumTrajectory(const std::string& path, TimeOrder order)
{
  std::ifstream in(path);
  if (!in)
    throw TrajectoryFileError("cannot open trajectory file '" + path + "'");
  return readTumTrajectory(in, path, order);
}

void writeTumTrajectory(std::ostream& out, const Trajectory& poses, const std::string& header)
{
  if (!header.empty())
    out << "# " << header << "\n";
  std::string line;
  Eigen::Quaterniond previous(1, 0, 0, 0);
  for (const auto& sp : poses)
  {
    const Eigen::Vector3d p = sp.T_world_camera.p_world_camera();
    // q and -q are the same rotation: keep each in the previous one's hemisphere so that the
    // written components are continuous (plots, and tools that interpolate them naively).
    Eigen::Quaterniond q = sp.T_world_camera.q_world_camera();
    if (q.dot(previous) < 0)
      q.coeffs() = -q.coeffs();
    previous = q;
    line.clear();
    for (const double v : {sp.t, p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()})
    {
      if (!line.empty())
        line += ' ';
      appendFixed(line, v, 9);
    }
    line += '\n';
    out << line;
  }
}

void appendFixed(std::string& out, double v, int decimals)
{
  char buf[400];  // the longest double in fixed notation: 309 digits, a sign, a point, 17 decimals
  decimals = decimals < 0 ? 0 : decimals > 17 ? 17 : decimals;
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed, decimals);
  if (r.ec == std::errc())
  {
    out.append(buf, r.ptr);
    return;
  }
  const int n = std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  out.append(buf, static_cast<size_t>(std::max(0, std::min<int>(n, sizeof(buf) - 1))));
}

void appendSeconds(std::string& out, int64_t t_ns)
{
  const bool negative = t_ns < 0;
  const uint64_t a = negative ? static_cast<uint64_t>(-(t_ns + 1)) + 1 : static_cast<uint64_t>(t_ns);
  char buf[32];
  char* p = buf;
  if (negative)
    *p++ = '-';
  p = std::to_chars(p, buf + sizeof(buf), a / 1000000000ULL).ptr;
  *p++ = '.';
  uint64_t fraction = a % 1000000000ULL;
  for (int i = 8; i >= 0; --i, fraction /= 10)
    p[i] = static_cast<char>('0' + fraction % 10);
  out.append(buf, p + 9);
}

void writeTumTrajectory(const std::string& path, const Trajectory& poses, const std::string& header)
{
  try
  {
    dvs_driver::writeFileChecked(path, [&](std::ostream& out) { writeTumTrajectory(out, poses, header); });
  }
  catch (const dvs_driver::WriteError& e)
  {
    throw TrajectoryFileError(std::string("cannot write trajectory file ") + e.what());
  }
}
}  // namespace dvs_calibration
