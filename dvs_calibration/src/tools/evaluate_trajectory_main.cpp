// evaluate_trajectory: the suite's one accuracy metric (trajectory_accuracy.h) on two TUM files.
//   evaluate_trajectory --groundtruth gt.txt --estimate est.txt [--from T0] [--to T1]
//                       [--max-age S] [--max-position M] [--max-orientation-deg D]
// Prints one JSON object (metres, degrees): the AccuracyReport's keys plus the files' sizes
// (groundtruth_poses, estimate_poses) and the first ground-truth time (groundtruth_start_s), so
// a caller (launch/scripts/evaluate_trajectory.py) needs no figure of its own. Exit 1 with a
// message naming the file on bad input.
#include <dvs_calibration/trajectory_accuracy.h>
#include <dvs_calibration/trajectory_file.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

using namespace dvs_calibration;

namespace
{
int usage(const std::string& why)
{
  std::cerr << "evaluate_trajectory: " << why
            << "\nusage: evaluate_trajectory --groundtruth gt.txt --estimate est.txt [--from T0] [--to T1] "
               "[--max-age S] [--max-position M] [--max-orientation-deg D]\n";
  return 2;
}

bool number(const std::string& text, double& v)
{
  char* end = nullptr;
  errno = 0;
  v = std::strtod(text.c_str(), &end);
  return !text.empty() && end == text.c_str() + text.size() && errno == 0;
}
}  // namespace

int main(int argc, char** argv)
{
  std::string gt_path, est_path;
  AccuracyOptions o;
  for (int i = 1; i < argc; i += 2)
  {
    const std::string a = argv[i];
    if (i + 1 >= argc)
      return usage(a + " needs a value");
    const std::string v = argv[i + 1];
    double x = 0;
    if (a == "--groundtruth")
      gt_path = v;
    else if (a == "--estimate")
      est_path = v;
    else if (a == "--from" || a == "--to" || a == "--max-age" || a == "--max-position" ||
             a == "--max-orientation-deg")
    {
      if (!number(v, x))
        return usage(a + ": '" + v + "' is not a number");
      if (a == "--from")
        o.from_s = x;
      else if (a == "--to")
        o.to_s = x;
      else if (a == "--max-age")
        o.max_age_s = x;
      else if (a == "--max-position")
        o.max_position_m = x;
      else
        o.max_orientation_rad = x * M_PI / 180.0;
    }
    else
      return usage("unknown option " + a);
  }
  if (gt_path.empty() || est_path.empty())
    return usage("--groundtruth and --estimate are required");
  try
  {
    const Trajectory gt = readTumTrajectory(gt_path);
    // A tracker may update several times on events with the same time stamp.
    const Trajectory est = readTumTrajectory(est_path, TimeOrder::NonDecreasing);
    if (gt.empty())
      throw std::runtime_error(gt_path + ": no poses");
    std::string json = evaluateTrajectory(est, gt, o).json();
    char extra[160];
    std::snprintf(extra, sizeof(extra), ", \"groundtruth_poses\": %zu, \"estimate_poses\": %zu, \"groundtruth_start_s\": %.6f}",
                  gt.size(), est.size(), gt.front().t);
    json.pop_back();  // the closing brace
    std::cout << json << extra << std::endl;
  }
  catch (const std::exception& e)
  {
    std::cerr << "evaluate_trajectory: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
