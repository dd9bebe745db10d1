#include "sim_scenario.h"

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>

namespace dvs_calibration
{
namespace testing
{
namespace
{
bool isExecutable(const std::string& path)
{
  struct stat st;
  return !path.empty() && ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && (st.st_mode & S_IXUSR);
}

void writeModulation(std::ostream& o, const SimScenario& s)
{
  const double low = s.backlight_flicker ? s.flicker_low : s.black;
  o << "      modulation: {type: square, frequency_hz: " << s.flicker_hz << ", low: " << low << ", high: " << s.white
    << ", duty: 0.5}\n";
}
}  // namespace

std::string writeSimScenario(const std::string& dir, const SimScenario& sc, const std::vector<ScreenPose>& poses)
{
  const EmulatedScreen& s = sc.screen;
  const double sp = s.spacing_m;
  const double x0 = -0.5 * (s.grid.cols - 1) * sp, y0 = 0.5 * (s.grid.rows - 1) * sp;  // circle (0,0), world
  const Eigen::Matrix3d R_world_screen = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const Eigen::Vector3d p_world_screen(x0, y0, 0);

  // Trajectory: each pose held still (4 equal samples: the interpolation is still between the
  // middle two), then a move to the next pose.
  const std::string traj_path = dir + "/trajectory.txt";
  {
    std::ofstream t(traj_path);
    if (!t)
      throw std::runtime_error("cannot write " + traj_path);
    t << "# t tx ty tz qx qy qz qw (T_world_camera), calibration poses dwelling " << sc.dwell_s << " s\n";
    t << std::setprecision(10);
    double time = 0;
    for (const ScreenPose& p : poses)
    {
      cv::Mat R;
      cv::Rodrigues(p.rvec, R);
      Eigen::Matrix3d R_cam_screen;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          R_cam_screen(i, j) = R.at<double>(i, j);
      const Eigen::Vector3d t_cam_screen(p.tvec[0], p.tvec[1], p.tvec[2]);
      const Eigen::Matrix3d R_world_cam = R_world_screen * R_cam_screen.transpose();
      const Eigen::Vector3d p_world_cam = R_world_screen * (-R_cam_screen.transpose() * t_cam_screen) + p_world_screen;
      const Eigen::Quaterniond q(R_world_cam);
      for (double dt : {0.0, 0.03, sc.dwell_s - 0.03, sc.dwell_s})
        t << time + dt << " " << p_world_cam.x() << " " << p_world_cam.y() << " " << p_world_cam.z() << " " << q.x()
          << " " << q.y() << " " << q.z() << " " << q.w() << "\n";
      time += sc.dwell_s + sc.move_s;
    }
  }

  const std::string cfg_path = dir + "/config.yaml";
  std::ofstream o(cfg_path);
  if (!o)
    throw std::runtime_error("cannot write " + cfg_path);
  const CameraIntrinsics& k = s.camera.intrinsics();
  o << std::setprecision(12);
  o << "# dvs_calibration end-to-end scenario: a " << s.grid.cols << "x" << s.grid.rows
    << " circle grid on a screen, " << (sc.backlight_flicker ? "backlight flicker" : "software blinking") << " at "
    << sc.flicker_hz << " Hz\n";
  o << "camera: {preset: dvs128, width: " << k.width << ", height: " << k.height << ", fx: " << k.fx
    << ", fy: " << k.fy << ", cx: " << k.cx << ", cy: " << k.cy << ", k1: " << k.k1 << ", k2: " << k.k2
    << ", p1: " << k.p1 << ", p2: " << k.p2 << ", k3: " << k.k3 << "}\n";
  o << "scene:\n  background_reflectance: " << sc.wall << "\n  polygons:\n";
  // The screen: black, a border of one spacing around the outer circles.
  const double bx0 = x0 - sp, bx1 = x0 + (s.grid.cols) * sp, by0 = y0 + sp, by1 = y0 - s.grid.rows * sp;
  o << "    - name: screen\n      reflectance: " << sc.black << "\n      in_map: false\n      vertices: [[" << bx0
    << ", " << by1 << "], [" << bx1 << ", " << by1 << "], [" << bx1 << ", " << by0 << "], [" << bx0 << ", " << by0
    << "]]\n";
  const double radius = s.radius_fraction * sp;
  constexpr int kVertices = 48;
  for (int r = 0; r < s.grid.rows; ++r)
    for (int c = 0; c < s.grid.cols; ++c)
    {
      const double cx = x0 + c * sp, cy = y0 - r * sp;
      o << "    - name: circle_" << r << "_" << c << "\n      reflectance: " << sc.white << "\n      in_map: false\n";
      writeModulation(o, sc);
      o << "      vertices: [";
      for (int i = 0; i < kVertices; ++i)
      {
        // Vertices on a circle of the same area as the true circle.
        const double a = 2 * M_PI * i / kVertices;
        const double rv = radius * std::sqrt(2 * M_PI / (kVertices * std::sin(2 * M_PI / kVertices)));
        o << (i ? ", " : "") << "[" << cx + rv * std::cos(a) << ", " << cy + rv * std::sin(a) << "]";
      }
      o << "]\n";
    }
  o << "trajectory:\n  file: {path: \"" << traj_path << "\"}\n";
  o << "events:\n  noise: {preset: " << sc.noise_preset << "}\n";
  // Coarser sampling of the moves between poses (only the still windows are used).
  o << "sampling:\n  max_pixel_motion: 0.5\n";
  return cfg_path;
}

std::vector<ScreenPose> orderForShortMoves(const EmulatedScreen& screen, const std::vector<ScreenPose>& poses)
{
  std::vector<ScreenPose> out;
  std::vector<bool> used(poses.size(), false);
  std::vector<std::vector<cv::Point2f>> px;
  for (const ScreenPose& p : poses)
    px.push_back(projectCenters(screen, p));
  size_t cur = 0;
  for (size_t n = 0; n < poses.size(); ++n)
  {
    used[cur] = true;
    out.push_back(poses[cur]);
    double best = 1e18;
    size_t next = cur;
    for (size_t j = 0; j < poses.size(); ++j)
    {
      if (used[j])
        continue;
      double d = 0;
      for (size_t k = 0; k < px[j].size(); ++k)
        d += cv::norm(px[j][k] - px[cur][k]);
      if (d < best)
      {
        best = d;
        next = j;
      }
    }
    cur = next;
  }
  return out;
}

std::string findSimulator(const std::string& devel_lib_dir)
{
  if (const char* env = std::getenv("DVS_SCREEN_SIM_SIMULATE"))
    return isExecutable(env) ? env : "";
  const std::string direct = devel_lib_dir + "/dvs_screen_sim/simulate";
  if (isExecutable(direct))
    return direct;
  if (const char* prefixes = std::getenv("CMAKE_PREFIX_PATH"))
  {
    std::stringstream ss(prefixes);
    std::string p;
    while (std::getline(ss, p, ':'))
      if (isExecutable(p + "/lib/dvs_screen_sim/simulate"))
        return p + "/lib/dvs_screen_sim/simulate";
  }
  return "";
}
}  // namespace testing
}  // namespace dvs_calibration
