// trajectory_error: accuracy of an estimated trajectory against ground truth (both TUM files,
// T_world_cam, same time base). Ground truth is interpolated at the estimate's times.
//   trajectory_error --estimate traj.txt --groundtruth groundtruth.txt [--from T0] [--to T1]
// Prints one line: n, position error mean/median/RMS [mm], orientation error mean/median/RMS
// [deg], and the covered fraction of the ground truth's time span.
#include <dvs_screen_sim/trajectory.h>
#include <dvs_screen_sim/trajectory_io.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

using namespace dvs_screen_sim;

int main(int argc, char** argv)
{
  std::string est_path, gt_path;
  double from = -1e300, to = 1e300;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--estimate")
      est_path = v;
    else if (a == "--groundtruth")
      gt_path = v;
    else if (a == "--from")
      from = std::atof(v.c_str());
    else if (a == "--to")
      to = std::atof(v.c_str());
    else
    {
      std::cerr << "trajectory_error: unknown argument " << a << "\n";
      return 2;
    }
  }
  if (est_path.empty() || gt_path.empty() || argc % 2 == 0)
  {
    std::cerr << "usage: trajectory_error --estimate traj.txt --groundtruth groundtruth.txt [--from T0] [--to T1]\n";
    return 2;
  }
  try
  {
    // A tracker may update several times on events with the same time stamp.
    const PoseTrajectory est = readTumTrajectory(est_path, TimeOrder::NonDecreasing);
    const PoseTrajectory gt = readTumTrajectory(gt_path);
    if (gt.size() < 2)
      throw std::runtime_error("ground truth has fewer than 2 poses");
    const double gt0 = gt.front().t, gt1 = gt.back().t;
    SampledTrajectory truth(gt);  // starts at 0: shift by gt0
    std::vector<double> dp, da;
    double first = 1e300, last = -1e300;
    for (const auto& e : est)
    {
      if (e.t < std::max(from, gt0) || e.t > std::min(to, gt1))
        continue;
      const Pose g = truth.poseAt(e.t - gt0);
      dp.push_back((e.T_world_cam.p - g.p).norm() * 1e3);
      da.push_back(e.T_world_cam.q.angularDistance(g.q) * 180.0 / M_PI);
      first = std::min(first, e.t);
      last = std::max(last, e.t);
    }
    if (dp.empty())
      throw std::runtime_error("no estimated pose inside the ground truth's time span");
    auto stats = [](std::vector<double> v, double& mean, double& median, double& rms) {
      double s = 0, ss = 0;
      for (double x : v)
      {
        s += x;
        ss += x * x;
      }
      mean = s / v.size();
      rms = std::sqrt(ss / v.size());
      std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
      median = v[v.size() / 2];
    };
    double pm, pmed, prms, am, amed, arms;
    stats(dp, pm, pmed, prms);
    stats(da, am, amed, arms);
    const double span = std::min(to, gt1) - std::max(from, gt0);
    std::printf("n %zu position_mm mean %.2f median %.2f rms %.2f orientation_deg mean %.3f median %.3f rms %.3f "
                "coverage %.3f\n",
                dp.size(), pm, pmed, prms, am, amed, arms, span > 0 ? (last - first) / span : 0.0);
  }
  catch (const std::exception& e)
  {
    std::cerr << "trajectory_error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
