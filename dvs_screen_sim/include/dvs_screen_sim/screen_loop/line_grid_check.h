#pragma once
// The thesis's check of the misalignment correction (ch. 3.4.1, Fig. 3.3): a grid of thin lines
// is displayed, and the DVS's events are compared with where the lines should be.
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/event.h>
#include <dvs_screen_sim/wall_pose.h>
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/screen_loop/gl_screen_renderer.h>

#include <vector>

namespace dvs_screen_sim
{
namespace screen_loop
{
/// nx vertical and ny horizontal lines in the wall plane z = 0, `spacing` apart, centred on
/// `centre`, each as long as the grid is wide/high.
std::vector<WorldLine> lineGrid(int nx, int ny, double spacing, const Eigen::Vector2d& centre = Eigen::Vector2d::Zero());

/// The same grid as lineGrid() as a simulator Scene (the pure-software reference: a DVS looking
/// at the virtual scene directly): lines `width` metres wide, cut at the crossings so the
/// polygons do not overlap, all with `modulation` (e.g. a square-wave blink), on a background
/// of `background`.
Scene lineGridScene(int nx, int ny, double spacing, double width, const IntensityModulation& modulation,
                    double background, const Eigen::Vector2d& centre = Eigen::Vector2d::Zero());

/// A segment in ideal (undistorted) DVS pixels.
struct ImageSegment
{
  Eigen::Vector2d a, b;
};
/// The lines as the DVS at the virtual camera pose T_world_camera would see them (ideal pixels,
/// Eq. 3.12); lines partly behind the camera are clipped at z = 0.01 m.
std::vector<ImageSegment> expectedImageLines(const dvs_calibration::CameraModel& camera, const Pose& T_world_camera,
                                             const std::vector<WorldLine>& lines);

struct LineDistanceStats
{
  size_t events_total = 0;
  size_t events_used = 0;         ///< events within max_distance of an expected line
  /// Mean distance of the events' undistorted pixel centres to the nearest expected line (the
  /// thesis's measure, 0.28 px on hardware). Includes the pixel grid's own spread.
  double mean_event_distance = 0;
  /// Mean |mean signed offset| of the events of each `chunk_px` long piece of each line: where
  /// the event cloud of a line lies relative to the expected line (misalignment only, not the
  /// pixel spread).
  double mean_line_offset = 0;
  size_t chunks = 0;
};
/// Events farther than max_distance from every expected line are ignored (noise, other
/// content); pieces with fewer than min_chunk_events events are skipped.
LineDistanceStats eventLineDistances(const dvs_driver::EventVector& events, const dvs_calibration::CameraModel& camera,
                                     const std::vector<ImageSegment>& expected, double max_distance = 2.0,
                                     double chunk_px = 8.0, size_t min_chunk_events = 10);
}  // namespace screen_loop
}  // namespace dvs_screen_sim
