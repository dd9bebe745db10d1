#pragma once
// Test fixture: a small, self-contained emulation of a DVS looking at a screen that shows the
// circle grid (flickering backlight or software blinking), used by the tests and the benchmark
// when the suite's simulator (dvs_screen_sim) is not run. Not a general simulator: a flat
// screen, dwelling poses, a per-toggle Poisson event model, background noise and hot pixels.
#include <dvs_calibration/camera_model.h>
#include <dvs_calibration/grid_detector.h>
#include <dvs_driver/event.h>

#include <opencv2/core.hpp>

#include <cstdint>
#include <random>
#include <vector>

namespace dvs_calibration
{
namespace testing
{
/// Pose of the screen in the camera: X_cam = R(rvec) * X_screen + t. Screen frame: origin at the
/// centre of circle (0, 0), x along the columns, y along the rows, z into the screen.
struct ScreenPose
{
  cv::Vec3d rvec;
  cv::Vec3d tvec;
};

struct EmulatedScreen
{
  CameraModel camera = CameraModel::dvs128();
  GridSize grid;
  double spacing_m = 0.03;
  double radius_fraction = 0.3;
  int supersample = 4;  ///< sub-samples per pixel side for the coverage

  /// true: the white parts flicker (backlight PWM) between `white` and `flicker_low * white`
  /// at flicker_hz; false: the pattern blinks in software between white and black at flicker_hz.
  bool backlight_flicker = true;
  double flicker_hz = 200.0;
  double flicker_low = 0.35;
  double black_level = 0.03;  ///< light of black pixels, relative to white
  /// Mean events per toggle and unit of log-intensity step (the DVS cannot follow a 200 Hz
  /// flicker fully: about 0.45 events per toggle for a fully white pixel, ~180 ev/s).
  double events_per_log_step = 0.45;
  double max_events_per_toggle = 8.0;
  double latency_jitter_s = 0.3e-3;
  double noise_rate_hz = 0.5;  ///< background activity per pixel
  int hot_pixels = 5;
  double hot_pixel_rate_hz = 100.0;
};

/// Fraction of each sensor pixel covered by white circles (CV_32F in [0, 1]).
cv::Mat renderGridCoverage(const EmulatedScreen& screen, const ScreenPose& pose);

/// Events of a still camera over [t0_ns, t0_ns + duration_ns) for a per-pixel white coverage.
/// Sorted by time.
dvs_driver::EventVector emulateEvents(const EmulatedScreen& screen, const cv::Mat& coverage, int64_t t0_ns,
                                      int64_t duration_ns, std::mt19937& rng);

/// Only noise (background activity and hot pixels), sorted.
dvs_driver::EventVector emulateNoise(const EmulatedScreen& screen, int64_t t0_ns, int64_t duration_ns,
                                     double rate_hz, std::mt19937& rng);

/// `n` poses with tilts up to max_tilt_deg that keep the whole grid inside the image with a
/// margin; deterministic for a seed.
std::vector<ScreenPose> calibrationPoses(const EmulatedScreen& screen, int n, double max_tilt_deg, uint32_t seed);

/// The true (distorted) pixel positions of the circle centres, grid order.
std::vector<cv::Point2f> projectCenters(const EmulatedScreen& screen, const ScreenPose& pose);

/// A whole recording: each pose dwelt on for dwell_ns, gap_ns of silence between poses.
dvs_driver::EventVector emulateRecording(const EmulatedScreen& screen, const std::vector<ScreenPose>& poses,
                                         int64_t dwell_ns, int64_t gap_ns, uint32_t seed);
}  // namespace testing
}  // namespace dvs_calibration
