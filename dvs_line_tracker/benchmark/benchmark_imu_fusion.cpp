// benchmark_imu_fusion: the line tracker with and without its IMU (issue 17) on the software
// DVS's 1200 deg/s flips (DVS128 with lens distortion, realistic noise, the MPU-6150-class IMU of
// dvs_screen_sim with random initial biases), at several distances and seeds, with and without a
// blackout of every event in the middle of the flip. Prints per run and as medians / worst:
//  - RMS position / orientation of the per-event poses, with and without IMU;
//  - with the blackout: the error right after it (the first pose after the gap), losses and
//    re-initialisations, RMS after the blackout;
//  - the IMU filter's covariance consistency: the fraction of 1 kHz samples whose error lies
//    inside the reported 1 and 3 sigma, per axis (position in the world, rotation in camera axes);
//    and the same for vision alone (the tracker's pose against the covariance ~odometry reports
//    without IMU).
//
//   rosrun dvs_line_tracker benchmark_imu_fusion [--seeds 1-5] [--distances 1.4,2.3] [--blackout 0.15]
//                                                [--params tracker.yaml] [--trace FILE]
// --trace writes per IMU sample of the IMU runs: t, position error (3), its sigmas (3), rotation
// error (3, camera axes), its sigmas (3)
#include <dvs_calibration/trajectory_accuracy.h>
#include <dvs_line_tracker/body_odometry.h>
#include <dvs_line_tracker/imu_propagator.h>
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_line_tracker/tracker_params.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/sim_config.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

using namespace dvs_line_tracker;

namespace
{
constexpr double kDeg = 180.0 / M_PI;
std::FILE* g_trace = nullptr;  ///< --trace: per IMU sample, t, errors and sigmas of the filter

struct RunResult
{
  dvs_calibration::AccuracyReport all, after;
  uint64_t losses = 0, reinits = 0, bridged = 0;
  double end_position_m = -1, end_orientation_rad = -1;  ///< first pose after the blackout
  uint64_t inside1 = 0, inside3 = 0, inside1_rot = 0, inside3_rot = 0, consistency_samples = 0;
  std::string imu_status;
};

struct Scenario
{
  dvs_screen_sim::SimConfig config;
  dvs_screen_sim::SimulationOutput output;
  std::unique_ptr<dvs_screen_sim::Trajectory> trajectory;
  dvs_calibration::Trajectory ground_truth;
};

Scenario simulate(double distance, uint64_t seed)
{
  Scenario s;
  std::ostringstream o;
  o << "trajectory: {flip: {distance: " << distance << "}}";
  s.config = dvs_screen_sim::resolveSimConfig("flip", YAML::Load(o.str()), seed);
  s.output = dvs_screen_sim::runSimulation(s.config);
  s.trajectory = dvs_screen_sim::makeTrajectory(s.config);
  for (const auto& g : s.output.groundtruth)
    s.ground_truth.push_back(g);
  return s;
}

/// The true camera pose at t_ns (simulation time + the configuration's offset).
Pose truth(const Scenario& s, int64_t t_ns)
{
  return s.trajectory->poseAt((t_ns - s.config.time_offset_ns) * 1e-9);
}

/// Whether the error of `estimate` at t_ns lies inside 1 and 3 sigma of `cov` (rotation error in
/// camera axes, position in the world), per axis.
void countConsistency(const Scenario& s, int64_t t_ns, const Pose& estimate, const Matrix6d& cov, RunResult& r)
{
  const Pose gt = truth(s, t_ns);
  const Eigen::Vector3d dp = estimate.p_world_camera() - gt.p_world_camera();
  const Eigen::AngleAxisd aa(estimate.R_camera_world * gt.R_world_camera());
  const Eigen::Vector3d dr = aa.angle() * aa.axis();
  for (int a = 0; a < 3; ++a)
  {
    const double sp = std::sqrt(cov(3 + a, 3 + a)), sr = std::sqrt(cov(a, a));
    r.inside1 += std::abs(dp[a]) <= sp;
    r.inside3 += std::abs(dp[a]) <= 3 * sp;
    r.inside1_rot += std::abs(dr[a]) <= sr;
    r.inside3_rot += std::abs(dr[a]) <= 3 * sr;
  }
  ++r.consistency_samples;
  if (g_trace)
    std::fprintf(g_trace, "%.4f %.5f %.5f %.5f %.5f %.5f %.5f %.6f %.6f %.6f %.6f %.6f %.6f\n", t_ns * 1e-9, dp.x(),
                 dp.y(), dp.z(), std::sqrt(cov(3, 3)), std::sqrt(cov(4, 4)), std::sqrt(cov(5, 5)), dr.x(), dr.y(),
                 dr.z(), std::sqrt(cov(0, 0)), std::sqrt(cov(1, 1)), std::sqrt(cov(2, 2)));
}

RunResult run(const Scenario& s, const LineTrackerParams& params, bool use_imu, double blackout_start, double blackout_s)
{
  LineTracker tracker(s.config.camera, defaultSquareMap(), params);
  std::shared_ptr<ImuPropagator> imu;
  if (use_imu)
  {
    imu = std::make_shared<ImuPropagator>(params.imu);
    tracker.setPropagator(imu);
  }
  const int64_t b0 = s.config.time_offset_ns + static_cast<int64_t>(blackout_start * 1e9);
  const int64_t b1 = b0 + static_cast<int64_t>(blackout_s * 1e9);
  RunResult r;
  dvs_calibration::Trajectory estimates;
  estimates.reserve(s.output.events.size());
  size_t next_imu = 0;
  int64_t next_check_ns = 0;
  bool after_gap_measured = blackout_s <= 0;
  for (const auto& e : s.output.events)
  {
    while (imu && next_imu < s.output.imu.size() && s.output.imu[next_imu].t_ns <= e.t_ns)
    {
      const int64_t t = s.output.imu[next_imu].t_ns;
      imu->addSample(s.output.imu[next_imu++]);
      ImuOdometry odo;
      if (!imu->odometry(t, odo))
        continue;
      countConsistency(s, t, odo.T_world_camera, odo.pose_covariance, r);
    }
    // Vision alone: the tracker's pose against its Gauss-Newton covariance, at every 1 ms.
    if (!imu && tracker.state() == TrackerState::kTracking && e.t_ns >= next_check_ns)
    {
      countConsistency(s, e.t_ns, tracker.pose(), visionPoseCovariance(tracker.estimatorState()) * kVisionOnlyCovarianceScale,
                       r);
      next_check_ns = e.t_ns + 1000000;
    }
    if (blackout_s > 0 && e.t_ns >= b0 && e.t_ns < b1)
      continue;
    const bool updated = tracker.processEvent(e);
    if (updated)
      estimates.push_back({e.t_ns * 1e-9, tracker.pose()});
    if (!after_gap_measured && e.t_ns >= b1)
    {
      after_gap_measured = true;
      if (tracker.state() == TrackerState::kTracking)
      {
        const Pose gt = truth(s, e.t_ns);
        r.end_position_m = positionError(tracker.pose(), gt);
        r.end_orientation_rad = orientationError(tracker.pose(), gt);
      }
    }
  }
  r.all = dvs_calibration::evaluateTrajectory(estimates, s.ground_truth, 0.05);
  if (blackout_s > 0)
    r.after = dvs_calibration::evaluateTrajectory(estimates, s.ground_truth, 0.05, b1 * 1e-9 + 0.001);
  r.losses = tracker.stats().losses;
  r.reinits = tracker.stats().reinitializations;
  r.bridged = tracker.stats().gaps_bridged;
  r.imu_status = imu ? toString(imu->status()) : "-";
  return r;
}

double median(std::vector<double> v)
{
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
double worst(const std::vector<double>& v) { return v.empty() ? 0 : *std::max_element(v.begin(), v.end()); }

std::vector<double> parseList(const std::string& text)
{
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
    out.push_back(std::atof(item.c_str()));
  return out;
}
}  // namespace

int main(int argc, char** argv)
{
  int seed_from = 1, seed_to = 5;
  std::vector<double> distances = {1.4, 2.3};
  double blackout = 0.15;
  LineTrackerParams params;
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc && std::sscanf(argv[i + 1], "%d-%d", &seed_from, &seed_to) >= 1)
    {
      if (!std::strchr(argv[i + 1], '-'))
        seed_to = seed_from;
      ++i;
    }
    else if (!std::strcmp(argv[i], "--distances") && i + 1 < argc)
      distances = parseList(argv[++i]);
    else if (!std::strcmp(argv[i], "--blackout") && i + 1 < argc)
      blackout = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--trace") && i + 1 < argc)
    {
      g_trace = std::fopen(argv[++i], "w");
      if (!g_trace)
      {
        std::fprintf(stderr, "benchmark_imu_fusion: cannot write %s\n", argv[i]);
        return 2;
      }
    }
    else if (!std::strcmp(argv[i], "--params") && i + 1 < argc)
    {
      try
      {
        loadTrackerParamsYaml(argv[++i], params);
      }
      catch (const std::exception& e)
      {
        std::fprintf(stderr, "benchmark_imu_fusion: %s\n", e.what());
        return 2;
      }
    }
    else
    {
      std::fprintf(stderr, "usage: benchmark_imu_fusion [--seeds A-B] [--distances D1,D2] [--blackout S] [--params tracker.yaml]\n"
                           "       [--trace FILE]\n");
      return 2;
    }
  }
  if (seed_to < seed_from || distances.empty() || !(blackout > 0 && blackout < 0.6))
  {
    std::fprintf(stderr, "benchmark_imu_fusion: bad --seeds, --distances or --blackout (0 < S < 0.6)\n");
    return 2;
  }
  std::printf("1200 deg/s flips (DVS128, lens distortion, realistic noise, MPU-6150-class IMU with random biases);\n"
              "blackout: no events for %.0f ms centred on the flip (t 0.75 s)\n\n",
              blackout * 1e3);
  std::printf("| distance | seed | RMS without IMU (cm / deg) | RMS with IMU (cm / deg) | change | blackout without IMU: "
              "losses / reinit | blackout with IMU: losses / reinit / bridged | error after blackout (cm / deg) | "
              "RMS after blackout (cm) | inside 1 / 3 sigma: position | rotation | vision alone: position | rotation |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (double d : distances)
  {
    std::vector<double> rms_vis, rms_imu, change, end_p, end_r, in1, in3, in1r, in3r, vin1, vin3, vin1r, vin3r;
    uint64_t imu_losses = 0, vis_losses = 0;
    for (int seed = seed_from; seed <= seed_to; ++seed)
    {
      const Scenario s = simulate(d, static_cast<uint64_t>(seed));
      const RunResult v = run(s, params, false, 0, 0);
      const RunResult m = run(s, params, true, 0, 0);
      const double start = 0.75 - blackout / 2;
      const RunResult vb = run(s, params, false, start, blackout);
      const RunResult mb = run(s, params, true, start, blackout);
      const double ch = m.all.rms_position_m / std::max(1e-9, v.all.rms_position_m) - 1.0;
      const double n = std::max<uint64_t>(1, 3 * m.consistency_samples);
      rms_vis.push_back(v.all.rms_position_m);
      rms_imu.push_back(m.all.rms_position_m);
      change.push_back(ch);
      end_p.push_back(mb.end_position_m < 0 ? 1e9 : mb.end_position_m);
      end_r.push_back(mb.end_orientation_rad < 0 ? 1e9 : mb.end_orientation_rad);
      in1.push_back(m.inside1 / n);
      in3.push_back(m.inside3 / n);
      in1r.push_back(m.inside1_rot / n);
      in3r.push_back(m.inside3_rot / n);
      const double nv = std::max<uint64_t>(1, 3 * v.consistency_samples);
      vin1.push_back(v.inside1 / nv);
      vin3.push_back(v.inside3 / nv);
      vin1r.push_back(v.inside1_rot / nv);
      vin3r.push_back(v.inside3_rot / nv);
      imu_losses += mb.losses + m.losses;
      vis_losses += vb.losses;
      std::printf("| %.1f m | %d | %.2f / %.2f | %.2f / %.2f | %+.0f %% | %llu / %llu | %llu / %llu / %llu | %s | %.2f | "
                  "%.0f / %.1f %% | %.0f / %.1f %% | %.0f / %.1f %% | %.0f / %.1f %% |\n",
                  d, seed, 100 * v.all.rms_position_m, v.all.rms_orientation_rad * kDeg, 100 * m.all.rms_position_m,
                  m.all.rms_orientation_rad * kDeg, 100 * ch, static_cast<unsigned long long>(vb.losses),
                  static_cast<unsigned long long>(vb.reinits), static_cast<unsigned long long>(mb.losses),
                  static_cast<unsigned long long>(mb.reinits), static_cast<unsigned long long>(mb.bridged),
                  mb.end_position_m < 0 ? "not tracking"
                                        : (std::to_string(100 * mb.end_position_m).substr(0, 4) + " / " +
                                           std::to_string(mb.end_orientation_rad * kDeg).substr(0, 4))
                                              .c_str(),
                  100 * mb.after.rms_position_m, 100 * in1.back(), 100 * in3.back(), 100 * in1r.back(),
                  100 * in3r.back(), 100 * vin1.back(), 100 * vin3.back(), 100 * vin1r.back(), 100 * vin3r.back());
      std::fflush(stdout);
    }
    std::printf("| **%.1f m: median (worst)** | | %.2f (%.2f) | %.2f (%.2f) | %+.0f %% (%+.0f %%) | %llu losses in all | "
                "%llu losses in all | %.2f (%.2f) cm / %.2f (%.2f) deg | | %.0f / %.1f %% | %.0f / %.1f %% | %.0f / %.1f %% | "
                "%.0f / %.1f %% |\n",
                d, 100 * median(rms_vis), 100 * worst(rms_vis), 100 * median(rms_imu), 100 * worst(rms_imu),
                100 * median(change), 100 * worst(change), static_cast<unsigned long long>(vis_losses),
                static_cast<unsigned long long>(imu_losses), 100 * median(end_p), 100 * worst(end_p),
                median(end_r) * kDeg, worst(end_r) * kDeg, 100 * median(in1), 100 * median(in3), 100 * median(in1r),
                100 * median(in3r), 100 * median(vin1), 100 * median(vin3), 100 * median(vin1r), 100 * median(vin3r));
  }
  return 0;
}
