#pragma once
// A (fullscreen) OpenGL window that draws the virtual scene for a real DVS filming the screen
// (thesis ch. 3): planar scenes (dvs_screen_sim::Scene polygons, world line quads) through the
// projection pipeline (the matrices of projection_pipeline.h go straight into GL_PROJECTION /
// GL_MODELVIEW), circles placed directly in viewport coordinates (the alignment pattern), and
// framebuffer read-back (glReadPixels) for the emulated screen in the loop.
//
// GLX on the X display named by $DISPLAY (works under Xvfb: `xvfb-run -a -s "-screen 0
// 1280x1024x24" ...`). Intensities are grey levels in [0, 1] written linearly to the 8-bit
// framebuffer (a linear display is assumed). Polygons must be convex (GL_POLYGON); painter's
// order, no depth test (z_clip = 0, Eq. 3.5). Not thread-safe: use it from the thread that
// created it.
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/screen_loop/alignment.h>

#include <Eigen/Core>

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace dvs_screen_sim
{
namespace screen_loop
{
class DisplayError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

struct WindowConfig
{
  bool fullscreen = true;   ///< the whole X screen (override-redirect + _NET_WM_STATE_FULLSCREEN)
  int width = 800;          ///< used when not fullscreen [screen px]
  int height = 600;
  bool vsync = true;        ///< ask for swap interval 1 (GLX_EXT/MESA_swap_control) when available
  std::string title = "dvs_screen_sim screen_loop";
};

/// A straight world line drawn as a quad of `width` metres in the plane z = 0 of the world.
struct WorldLine
{
  Eigen::Vector3d a, b;
};

/// What the screen-in-the-loop procedure draws a frame with (GlScreenRenderer; a recording
/// fake in the procedure's tests).
class ScreenCanvas
{
public:
  virtual ~ScreenCanvas() = default;
  virtual int width() const = 0;
  virtual int height() const = 0;
  /// Clear the back buffer to a grey level.
  virtual void clear(double intensity) = 0;
  /// Load P (GL_PROJECTION, e.g. Hbar K_O) and the view matrix M_O (GL_MODELVIEW).
  virtual void setMatrices(const Eigen::Matrix4d& projection, const Eigen::Matrix4d& view) = 0;
  /// The scene's polygons at time t (intensities incl. modulation), in order, world z = 0.
  /// (The wall background is not drawn: call clear(scene.background_reflectance) first.)
  virtual void drawScenePolygons(const Scene& scene, double t) = 0;
  /// World lines as quads `width` metres wide in the wall plane (through the loaded matrices).
  virtual void drawWorldLines(const std::vector<WorldLine>& lines, double width, double intensity) = 0;
  /// Filled circles directly in viewport coordinates (matrices bypassed), radius in window
  /// pixels (round on screen whatever the window's aspect ratio).
  virtual void drawViewportDiscs(const Points2d& centres_vp, double radius_px, double intensity, int segments = 64) = 0;
};

class GlScreenRenderer : public ScreenCanvas
{
public:
  /// Opens the window and its GL context (retrying the display for up to 2 s). Throws
  /// DisplayError when $DISPLAY cannot be opened or no suitable visual exists (the message says
  /// so). Losing the display later ends the process (exit code 1) with a message.
  explicit GlScreenRenderer(const WindowConfig& config = WindowConfig());
  ~GlScreenRenderer();
  GlScreenRenderer(const GlScreenRenderer&) = delete;
  GlScreenRenderer& operator=(const GlScreenRenderer&) = delete;

  int width() const override { return width_; }
  int height() const override { return height_; }
  bool vsyncEnabled() const { return vsync_; }

  void clear(double intensity) override;
  void setMatrices(const Eigen::Matrix4d& projection, const Eigen::Matrix4d& view) override;
  void drawScenePolygons(const Scene& scene, double t) override;
  void drawWorldLines(const std::vector<WorldLine>& lines, double width, double intensity) override;
  void drawViewportDiscs(const Points2d& centres_vp, double radius_px, double intensity, int segments = 64) override;
  /// Read the back buffer (what the next swap shows): grey levels in [0, 1], row-major, row 0 =
  /// the window's TOP row, width() * height() values.
  void readBackBuffer(std::vector<float>& grey);
  /// Show the frame; returns after the swap (blocks on vsync when enabled) and glFinish.
  void swap();
  /// Process pending X events; returns false once a key was pressed or the window closed.
  bool pollEvents();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int width_ = 0, height_ = 0;
  bool vsync_ = false;
  std::vector<unsigned char> rgb_;
};

/// True when an X display can be opened ($DISPLAY set and reachable).
bool displayAvailable();

/// For offline programs and tests: when $DISPLAY is unset, re-run this program under
/// `xvfb-run -a -n N -s "-screen 0 1280x1024x24 -noreset"` (N derived from the pid, away from the usual
/// 99). Returns only when a display is set (or after a failed exec: then it returns false and
/// says why on stderr).
bool reexecUnderXvfbIfNoDisplay(int argc, char** argv);
}  // namespace screen_loop
}  // namespace dvs_screen_sim
