#include "sweep_scene.h"

#include <dvs_calibration/pose.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace dvs_line_tracker
{
namespace
{
constexpr double kDeg = M_PI / 180.0;

/// Camera motion of the sweep: an orbit of the camera centre in the wall's plane around its start
/// position, the optical axis always through a fixed point, a sinusoidal roll sway, and
/// optionally a flip (a full roll with a Gaussian rate profile while rising and falling back).
class SweepTrajectory : public dvs_screen_sim::Trajectory
{
public:
  struct Params
  {
    Eigen::Vector3d start{0, 0, 1};
    Eigen::Vector3d look_at{0, 0, 0};
    double orbit_radius = 0.05;  ///< [m]
    double orbit_speed = 0.1;    ///< [m/s]
    double orbit_phase = 0;      ///< [rad]
    double roll0 = 0;            ///< [rad]
    double sway_peak_rate = 15 * kDeg;  ///< [rad/s]
    double sway_frequency = 0.25;       ///< [Hz]
    double flip_time = -1;       ///< centre of the flip [s] (< 0: none)
    double flip_peak_rate = 2000 * kDeg;
    double flip_rise = 0.3;      ///< [m]
    double flip_repeat = 0;      ///< > 0: another flip every this many seconds [s]
    double duration = 1.5;
  };
  explicit SweepTrajectory(const Params& p) : p_(p) {}

  dvs_calibration::Pose poseAt(double t) const override
  {
    const Eigen::Vector3d up(0, 1, 0);
    const double w = p_.orbit_speed / p_.orbit_radius;
    Eigen::Vector3d p = p_.start + p_.orbit_radius * Eigen::Vector3d(std::cos(w * t + p_.orbit_phase) - std::cos(p_.orbit_phase),
                                                                     std::sin(w * t + p_.orbit_phase) - std::sin(p_.orbit_phase), 0);
    const double f = 2 * M_PI * p_.sway_frequency;
    double roll = p_.roll0 + p_.sway_peak_rate / f * std::sin(f * t);
    // Gaussian roll rate with peak flip_peak_rate integrating to one turn.
    const double sigma = std::sqrt(2 * M_PI) / p_.flip_peak_rate;
    const double sh = 0.15;
    for (double flip = p_.flip_time; flip >= 0; flip += p_.flip_repeat)
    {
      roll += M_PI * (1 + std::erf((t - flip) / (sigma * std::sqrt(2.0))));
      p += up * p_.flip_rise * std::exp(-0.5 * std::pow((t - flip) / sh, 2));
      if (p_.flip_repeat <= 0 || flip > t + 1.0)
        break;
    }
    return dvs_calibration::lookAt(p, p_.look_at, up, roll);
  }
  double naturalDuration() const override { return p_.duration; }

private:
  Params p_;
};

dvs_calibration::CameraModel makeCamera(const SweepSceneSpec& s)
{
  dvs_calibration::CameraIntrinsics k;
  k.width = s.width;
  k.height = s.height;
  k.cx = (s.width - 1) / 2.0;
  k.cy = (s.height - 1) / 2.0;
  k.k1 = s.k1;
  // Real lenses with strong barrel distortion bend back (k2 > 0); the smallest k2 that keeps
  // the lens one-to-one up to the image corners is used.
  for (double k2 : {0.0, 0.02, 0.05, 0.1, 0.2, 0.3})
  {
    k.k2 = k2;
    const double xu = std::tan(s.hfov_deg * kDeg / 2);
    const double xd = xu * (1 + s.k1 * xu * xu + k2 * xu * xu * xu * xu);
    if (xd <= 0)
      continue;
    k.fx = k.fy = (s.width / 2.0) / xd;
    try
    {
      return dvs_calibration::CameraModel(k);
    }
    catch (const std::exception&)
    {
    }
  }
  throw std::invalid_argument("sweep scene: no one-to-one lens with hfov " + std::to_string(s.hfov_deg) +
                              " deg and k1 " + std::to_string(s.k1));
}

dvs_screen_sim::ScenePolygon squarePolygon(const std::string& name, double cx, double side, double reflectance)
{
  dvs_screen_sim::ScenePolygon p;
  p.name = name;
  p.reflectance = reflectance;
  const double h = side / 2;
  p.vertices = {{cx - h, -h}, {cx + h, -h}, {cx + h, h}, {cx - h, h}};
  return p;
}

dvs_screen_sim::ScenePolygon trianglePolygon(const std::string& name, double cx, double side, double reflectance)
{
  dvs_screen_sim::ScenePolygon p;
  p.name = name;
  p.reflectance = reflectance;
  const double h = side * std::sqrt(3.0) / 2;
  p.vertices = {{cx - side / 2, -h / 2}, {cx + side / 2, -h / 2}, {cx, h / 2}};
  return p;
}

dvs_screen_sim::NoiseConfig makeNoise(SweepNoise n)
{
  // The simulator's DVS128-like preset, with the background and jitter levels.
  dvs_screen_sim::NoiseConfig c = dvs_screen_sim::noisePreset("realistic");
  c.latency_jitter = 1e-4;
  c.background_rate = n == SweepNoise::kLowContrast ? 0.5 : 0.2;
  if (n == SweepNoise::kHeavy)
  {
    c.threshold_sigma = 0.06;  // 20 % of C = 0.3
    c.latency = 1e-3;
    c.latency_jitter = 1e-3;
    c.background_rate = 2.0;
    c.hot_pixel_fraction = 0.002;
    c.hot_pixel_rate = 20;
  }
  return c;
}

double uniform(std::mt19937_64& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
}  // namespace

SweepScene buildSweepScene(const SweepSceneSpec& spec)
{
  if (spec.coverage <= 0.05 || spec.coverage > 1.0)
    throw std::invalid_argument("sweep scene: coverage must be in (0.05, 1]");
  SweepScene s;
  s.spec = spec;
  std::mt19937_64 rng(spec.seed * 7919 + 17);
  s.camera = makeCamera(spec);

  // Image extent in undistorted normalised coordinates along the centre lines.
  const auto& in = s.camera.intrinsics();
  const double half_w = s.camera.pixelToUndistortedNormalized({spec.width - 0.5, in.cy}).x();
  const double half_h = s.camera.pixelToUndistortedNormalized({in.cx, spec.height - 0.5}).y();

  // The polygon covers `coverage` of the image height: distance = side / (coverage * height).
  const bool multi = spec.map == SweepMap::kTwoSquares || spec.map == SweepMap::kSquareTriangle;
  double coverage = spec.coverage;
  if (multi)  // both polygons fit side by side (2.3 sides wide) unless the view is partial
    coverage = std::min(coverage, 0.85 * (half_w / half_h) / 2.3);
  // A square seen 60 deg off its normal comes side / 2 * sin(60 deg) nearer at its near side:
  // close and through a wide lens, that side passed behind the camera (scene 44 of the sweep:
  // two corners at or behind the camera for the whole run, no pose possible). It stays at least
  // 30 % of the distance in front.
  if (spec.map == SweepMap::kSteepSquare)
    coverage = std::min(coverage, 0.7 / (std::sin(60 * kDeg) * half_h));
  double side = 0.9;
  double distance = side / (coverage * 2 * half_h);
  const double clamped = std::clamp(distance, 0.3, 5.0);
  side *= clamped / distance;
  distance = clamped;
  s.distance = distance;
  s.polygon_side = side;
  s.coverage = side / (distance * 2 * half_h);

  const bool low_contrast = spec.noise == SweepNoise::kLowContrast;
  const double dark = low_contrast ? 0.3 : 0.1;
  s.scene.background_reflectance = 0.9;
  double map_half_width = side / 2;
  switch (spec.map)
  {
    case SweepMap::kSquare:
    case SweepMap::kSteepSquare:
      s.scene.polygons.push_back(squarePolygon("square", 0, side, dark));
      break;
    case SweepMap::kTwoSquares:
      s.scene.polygons.push_back(squarePolygon("left", -0.65 * side, side, dark));
      s.scene.polygons.push_back(squarePolygon("right", 0.65 * side, side, dark));
      map_half_width = 1.15 * side;
      break;
    case SweepMap::kSquareTriangle:
      s.scene.polygons.push_back(squarePolygon("square", -0.65 * side, side, dark));
      s.scene.polygons.push_back(trianglePolygon("triangle", 0.65 * side, side, dark));
      map_half_width = 1.15 * side;
      break;
  }
  s.scene.finalize();
  for (const auto& poly : s.scene.polygons)
    for (size_t i = 0; i < poly.vertices.size(); ++i)
    {
      const auto& a = poly.vertices[i];
      const auto& b = poly.vertices[(i + 1) % poly.vertices.size()];
      s.map.segments.push_back({Eigen::Vector3d(a.x(), a.y(), 0), Eigen::Vector3d(b.x(), b.y(), 0)});
    }
  finalizeLineMap(s.map, "sweep map");

  SweepTrajectory::Params tp;
  // Viewing direction: straight at the wall, or 60 deg off the normal (to either side).
  const double side_sign = uniform(rng, 0, 1) < 0.5 ? -1 : 1;
  const double yaw = spec.map == SweepMap::kSteepSquare ? 60 * kDeg * side_sign : uniform(rng, -10, 10) * kDeg;
  tp.start = s.target + distance * Eigen::Vector3d(std::sin(yaw), uniform(rng, -0.05, 0.05), std::cos(yaw));
  tp.look_at = s.target;
  tp.roll0 = uniform(rng, -20, 20) * kDeg;
  if (spec.partial)
  {
    // The partial views: a corner, and so part of two sides, outside the image at the
    // start (every side stays partly in view). The map is rolled by 15-35 deg and the view
    // turned so that its outermost corner lies 20 % of a polygon side beyond the right (odd
    // seeds) or the bottom (even seeds) image border.
    const double roll = (uniform(rng, 0, 1) < 0.5 ? -1 : 1) * uniform(rng, 15, 35) * kDeg;
    tp.roll0 = roll;
    const double reach = map_half_width - side / 2 + side / 2 * (std::cos(roll) + std::abs(std::sin(roll)));
    const Eigen::Vector3d right = Eigen::Vector3d(std::cos(yaw), 0, -std::sin(yaw));
    if (spec.seed % 2 == 1)
      tp.look_at -= (half_w * distance + 0.2 * side - reach) * right;
    else
      tp.look_at += (half_h * distance + 0.2 * side - reach) * Eigen::Vector3d::UnitY();
  }
  tp.orbit_phase = uniform(rng, 0, 2 * M_PI);
  switch (spec.motion)
  {
    case SweepMotion::kSlow:
      tp.orbit_speed = 0.1;
      tp.orbit_radius = std::min(0.1, 0.1 * distance);
      tp.sway_peak_rate = 15 * kDeg;
      tp.sway_frequency = 0.25;
      tp.duration = 1.5;
      break;
    case SweepMotion::kHandheld:
      tp.orbit_speed = 0.4;
      tp.orbit_radius = std::min(0.15, 0.15 * distance);
      tp.sway_peak_rate = 60 * kDeg;
      tp.sway_frequency = 0.5;
      tp.duration = 1.5;
      break;
    case SweepMotion::kFlip:
      tp.orbit_speed = 0.05;
      tp.orbit_radius = std::min(0.03, 0.05 * distance);
      tp.sway_peak_rate = 5 * kDeg;
      tp.sway_frequency = 0.5;
      tp.flip_time = 0.55;
      tp.flip_peak_rate = 2000 * kDeg;
      tp.flip_rise = std::min(0.5, 0.25 * distance);
      tp.flip_repeat = spec.flip_repeat_s;
      tp.duration = 1.1;
      break;
  }
  s.duration = tp.duration;
  s.trajectory = std::make_shared<SweepTrajectory>(tp);
  s.events.noise = makeNoise(spec.noise);
  s.events.validate();
  return s;
}

std::vector<SweepSceneSpec> sweepSceneSpecs(int count)
{
  struct Sensor
  {
    int w, h;
  };
  const Sensor sensors[] = {{128, 128}, {240, 180}, {346, 260}, {640, 480}};
  struct Lens
  {
    double fov_lo, fov_hi, k1_lo, k1_hi;
  };
  const Lens lenses[] = {{40, 50, -0.05, 0.1}, {55, 70, -0.15, 0.05}, {75, 85, -0.3, -0.15}, {95, 110, -0.2, 0.0}};
  const double coverage_lo[] = {0.15, 0.35, 0.7}, coverage_hi[] = {0.3, 0.6, 0.95};
  std::vector<SweepSceneSpec> specs;
  for (int i = 0; i < count; ++i)
  {
    // Every sensor with every lens class (16); the repetitions rotate the other axes so that
    // each sensor and lens meets every motion, map, noise and distance class.
    const int s = i % 4, l = (i / 4) % 4, rep = i / 16;
    std::mt19937_64 rng(1000 + i);
    SweepSceneSpec spec;
    spec.seed = static_cast<uint64_t>(i + 1);
    spec.width = sensors[s].w;
    spec.height = sensors[s].h;
    spec.hfov_deg = uniform(rng, lenses[l].fov_lo, lenses[l].fov_hi);
    spec.k1 = uniform(rng, lenses[l].k1_lo, lenses[l].k1_hi);
    const int c = (l + rep + 2 * s) % 3;
    spec.coverage = uniform(rng, coverage_lo[c], coverage_hi[c]);
    spec.motion = static_cast<SweepMotion>((s + l + rep) % 3);
    spec.map = static_cast<SweepMap>((s + 3 * l + rep) % 4);
    spec.noise = static_cast<SweepNoise>((2 * s + l + 2 * rep) % 3);
    spec.partial = (s + l + 2 * rep) % 4 == 1;
    specs.push_back(spec);
  }
  return specs;
}

std::string sensorLabel(const SweepSceneSpec& s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

std::string lensLabel(const SweepSceneSpec& s)
{
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0f deg, k1 %+.2f", s.hfov_deg, s.k1);
  return buf;
}

const char* motionLabel(SweepMotion m)
{
  switch (m)
  {
    case SweepMotion::kSlow:
      return "slow";
    case SweepMotion::kHandheld:
      return "hand-held";
    case SweepMotion::kFlip:
      return "flip 2000 deg/s";
  }
  return "?";
}

const char* mapLabel(SweepMap m)
{
  switch (m)
  {
    case SweepMap::kSquare:
      return "square";
    case SweepMap::kTwoSquares:
      return "two squares";
    case SweepMap::kSquareTriangle:
      return "square + triangle";
    case SweepMap::kSteepSquare:
      return "square at 60 deg";
  }
  return "?";
}

const char* noiseLabel(SweepNoise n)
{
  switch (n)
  {
    case SweepNoise::kRealistic:
      return "realistic";
    case SweepNoise::kHeavy:
      return "heavy";
    case SweepNoise::kLowContrast:
      return "contrast 3";
  }
  return "?";
}
}  // namespace dvs_line_tracker
