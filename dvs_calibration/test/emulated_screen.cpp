#include "emulated_screen.h"

#include <Eigen/LU>
#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>

namespace dvs_calibration
{
namespace testing
{
namespace
{
void sortByTime(dvs_driver::EventVector& ev)
{
  std::stable_sort(ev.begin(), ev.end(),
                   [](const dvs_driver::Event& a, const dvs_driver::Event& b) { return a.t_ns < b.t_ns; });
}
}  // namespace

cv::Mat renderGridCoverage(const EmulatedScreen& s, const ScreenPose& pose)
{
  const int w = s.camera.width(), h = s.camera.height();
  cv::Mat R;
  cv::Rodrigues(pose.rvec, R);
  const Eigen::Vector3d r0(R.at<double>(0, 0), R.at<double>(1, 0), R.at<double>(2, 0));
  const Eigen::Vector3d r1(R.at<double>(0, 1), R.at<double>(1, 1), R.at<double>(2, 1));
  const Eigen::Vector3d t(pose.tvec[0], pose.tvec[1], pose.tvec[2]);
  const double radius = s.radius_fraction * s.spacing_m;
  cv::Mat cov = cv::Mat::zeros(h, w, CV_32F);
  const int n = std::max(1, s.supersample);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
    {
      int hits = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
        {
          const Eigen::Vector2d px(x - 0.5 + (i + 0.5) / n, y - 0.5 + (j + 0.5) / n);
          const Eigen::Vector2d xn = s.camera.pixelToUndistortedNormalized(px);
          const Eigen::Vector3d d(xn.x(), xn.y(), 1.0);
          // Solve u * r0 + v * r1 - lambda * d = -t.
          Eigen::Matrix3d A;
          A.col(0) = r0;
          A.col(1) = r1;
          A.col(2) = -d;
          const Eigen::Vector3d sol = A.fullPivLu().solve(-t);
          if (sol.z() <= 0)
            continue;
          const double u = sol.x() / s.spacing_m, v = sol.y() / s.spacing_m;
          const double cu = std::round(u), cv_ = std::round(v);
          if (cu < 0 || cv_ < 0 || cu >= s.grid.cols || cv_ >= s.grid.rows)
            continue;
          const double du = (u - cu) * s.spacing_m, dv = (v - cv_) * s.spacing_m;
          if (du * du + dv * dv <= radius * radius)
            ++hits;
        }
      cov.at<float>(y, x) = static_cast<float>(hits) / static_cast<float>(n * n);
    }
  return cov;
}

dvs_driver::EventVector emulateNoise(const EmulatedScreen& s, int64_t t0_ns, int64_t duration_ns, double rate_hz,
                                     std::mt19937& rng)
{
  dvs_driver::EventVector ev;
  const int w = s.camera.width(), h = s.camera.height();
  const double dur = duration_ns * 1e-9;
  std::uniform_int_distribution<int> ux(0, w - 1), uy(0, h - 1), coin(0, 1);
  std::uniform_real_distribution<double> ut(0.0, 1.0);
  std::poisson_distribution<long> total(std::max(1e-9, rate_hz * w * h * dur));
  const long n = total(rng);
  for (long i = 0; i < n; ++i)
  {
    dvs_driver::Event e;
    e.t_ns = t0_ns + static_cast<int64_t>(ut(rng) * static_cast<double>(duration_ns));
    e.x = static_cast<uint16_t>(ux(rng));
    e.y = static_cast<uint16_t>(uy(rng));
    e.polarity = coin(rng) == 1;
    ev.push_back(e);
  }
  // Hot pixels: fixed positions (seeded by the sensor size), high rate.
  std::mt19937 hot_rng(static_cast<uint32_t>(w * 7919 + h));
  for (int k = 0; k < s.hot_pixels; ++k)
  {
    const uint16_t x = static_cast<uint16_t>(ux(hot_rng)), y = static_cast<uint16_t>(uy(hot_rng));
    std::poisson_distribution<long> pn(s.hot_pixel_rate_hz * dur);
    const long m = pn(rng);
    for (long i = 0; i < m; ++i)
      ev.push_back({t0_ns + static_cast<int64_t>(ut(rng) * static_cast<double>(duration_ns)), x, y, coin(rng) == 1});
  }
  sortByTime(ev);
  return ev;
}

dvs_driver::EventVector emulateEvents(const EmulatedScreen& s, const cv::Mat& coverage, int64_t t0_ns,
                                      int64_t duration_ns, std::mt19937& rng)
{
  dvs_driver::EventVector ev = emulateNoise(s, t0_ns, duration_ns, s.noise_rate_hz, rng);
  const double half_period_ns = 0.5e9 / s.flicker_hz;
  const double low = s.backlight_flicker ? s.flicker_low : 0.0;
  std::exponential_distribution<double> jitter(1.0 / std::max(1e-6, s.latency_jitter_s));
  for (int y = 0; y < coverage.rows; ++y)
    for (int x = 0; x < coverage.cols; ++x)
    {
      const double c = coverage.at<float>(y, x);
      if (c <= 0)
        continue;
      const double step = std::log(s.black_level + c) - std::log(s.black_level + c * low);
      const double mean = std::min(s.max_events_per_toggle, s.events_per_log_step * step);
      std::poisson_distribution<int> pn(mean);
      // Toggle k happens at k * half_period; even toggles turn the white parts on (ON events).
      const int64_t k0 = static_cast<int64_t>(std::ceil(t0_ns / half_period_ns));
      for (int64_t k = k0;; ++k)
      {
        const double tk = k * half_period_ns;
        if (tk >= t0_ns + duration_ns)
          break;
        const bool on = (k % 2) == 0;
        const int m = pn(rng);
        for (int i = 0; i < m; ++i)
        {
          const int64_t t = static_cast<int64_t>(tk + jitter(rng) * 1e9);
          if (t < t0_ns + duration_ns)
            ev.push_back({t, static_cast<uint16_t>(x), static_cast<uint16_t>(y), on});
        }
      }
    }
  sortByTime(ev);
  return ev;
}

std::vector<cv::Point2f> projectCenters(const EmulatedScreen& s, const ScreenPose& pose)
{
  const std::vector<cv::Point3f> obj = gridObjectPoints(s.grid, s.spacing_m);
  const CameraIntrinsics& k = s.camera.intrinsics();
  const cv::Mat K = (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  const cv::Mat D = (cv::Mat_<double>(1, 5) << k.k1, k.k2, k.p1, k.p2, k.k3);
  std::vector<cv::Point2f> px;
  cv::projectPoints(obj, pose.rvec, pose.tvec, K, D, px);
  return px;
}

std::vector<ScreenPose> calibrationPoses(const EmulatedScreen& s, int n, double max_tilt_deg, uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const CameraIntrinsics& k = s.camera.intrinsics();
  const double board_w = (s.grid.cols - 1) * s.spacing_m, board_h = (s.grid.rows - 1) * s.spacing_m;
  // Distance at which the board spans ~60% of the image.
  const double d0 = k.fx * std::max(board_w, board_h) / (0.6 * std::min(s.camera.width(), s.camera.height()));
  const double margin = 2.0 + s.radius_fraction * s.spacing_m * k.fx / d0 * 1.5;
  std::vector<ScreenPose> poses;
  int attempts = 0;
  while (static_cast<int>(poses.size()) < n && attempts < 100000)
  {
    ++attempts;
    // Spread the tilts evenly over [0, max] so that strong tilts are present.
    const double tilt = max_tilt_deg * CV_PI / 180.0 * (0.15 + 0.85 * ((poses.size() % 5) / 4.0)) * (0.9 + 0.1 * u01(rng));
    const double axis_angle = 2 * CV_PI * u01(rng);
    const double roll = (u01(rng) - 0.5) * 60.0 * CV_PI / 180.0;
    cv::Mat R_tilt, R_roll;
    cv::Rodrigues(cv::Vec3d(std::cos(axis_angle) * tilt, std::sin(axis_angle) * tilt, 0), R_tilt);
    cv::Rodrigues(cv::Vec3d(0, 0, roll), R_roll);
    const cv::Mat R = R_tilt * R_roll;
    const double dist = d0 * (0.8 + 0.5 * u01(rng));
    const cv::Vec3d aim((u01(rng) - 0.5) * 0.4, (u01(rng) - 0.5) * 0.4, 1.0);
    // Board centre on the aim ray at `dist`; origin at circle (0, 0).
    const cv::Mat centre_board = (cv::Mat_<double>(3, 1) << board_w / 2, board_h / 2, 0);
    const cv::Mat centre_cam = (cv::Mat_<double>(3, 1) << aim[0] * dist, aim[1] * dist, dist);
    const cv::Mat t = centre_cam - R * centre_board;
    ScreenPose p;
    cv::Mat rv;
    cv::Rodrigues(R, rv);
    p.rvec = cv::Vec3d(rv.at<double>(0), rv.at<double>(1), rv.at<double>(2));
    p.tvec = cv::Vec3d(t.at<double>(0), t.at<double>(1), t.at<double>(2));
    bool inside = true;
    for (const cv::Point2f& c : projectCenters(s, p))
      if (c.x < margin || c.y < margin || c.x > s.camera.width() - 1 - margin || c.y > s.camera.height() - 1 - margin)
        inside = false;
    if (inside)
      poses.push_back(p);
  }
  return poses;
}

dvs_driver::EventVector emulateRecording(const EmulatedScreen& s, const std::vector<ScreenPose>& poses,
                                         int64_t dwell_ns, int64_t gap_ns, uint32_t seed)
{
  std::mt19937 rng(seed);
  dvs_driver::EventVector all;
  int64_t t = 1000000000;  // start at 1 s
  for (const ScreenPose& p : poses)
  {
    const cv::Mat cov = renderGridCoverage(s, p);
    dvs_driver::EventVector ev = emulateEvents(s, cov, t, dwell_ns, rng);
    all.insert(all.end(), ev.begin(), ev.end());
    t += dwell_ns;
    dvs_driver::EventVector gap = emulateNoise(s, t, gap_ns, s.noise_rate_hz, rng);
    all.insert(all.end(), gap.begin(), gap.end());
    t += gap_ns;
  }
  return all;
}
}  // namespace testing
}  // namespace dvs_calibration
