#pragma once
// The screen in the loop without hardware: the OpenGL window, read back after each frame, is the
// content of an emissive SceneImage (a monitor on the wall of dvs_screen_sim's world) that the
// software DVS films. Each refresh (update_period) draws the next frame with `draw_frame`, reads
// the back buffer into the image's texels and swaps.
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/screen_loop/gl_screen_renderer.h>

#include <functional>

namespace dvs_screen_sim
{
namespace screen_loop
{
struct MonitorGeometry
{
  Eigen::Vector2d top_left{-0.2, 0.16};  ///< wall coordinates of the screen's top-left corner [m]
  double pixel_pitch = 0.0005;           ///< [m] per screen pixel (square pixels)
  double black_level = 0.0;              ///< intensity of a black pixel (backlight leak)
  double white_level = 1.0;              ///< intensity of a white pixel
  /// [s] pixel response time: a new frame's luminance is reached linearly over this time after
  /// the refresh (LCDs: a few ms grey-to-grey); 0: an ideal, instantaneous screen.
  double response_time = 0.0;
};

/// Draws frame `frame_index` (the renderer is the current GL context) into the back buffer.
using FrameDrawer = std::function<void(int64_t frame_index, GlScreenRenderer& gl)>;

/// A SceneImage of gl.width() x gl.height() texels showing what `draw_frame` draws, refreshed
/// every `refresh_period` seconds. `gl` must outlive the image (and every copy of the scene).
SceneImage makeVirtualMonitor(GlScreenRenderer& gl, const MonitorGeometry& geometry, double refresh_period,
                              FrameDrawer draw_frame);

/// The wall point of a screen position given in window pixels (x right, y down, continuous).
inline Eigen::Vector3d monitorWallPoint(const MonitorGeometry& g, const Eigen::Vector2d& window_px)
{
  return {g.top_left.x() + window_px.x() * g.pixel_pitch, g.top_left.y() - window_px.y() * g.pixel_pitch, 0.0};
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
