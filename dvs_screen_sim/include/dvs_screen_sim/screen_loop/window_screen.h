#pragma once
// The real screen of the screen in the loop: the OpenGL window refreshing in wall-clock time
// (vsync'd swaps), its screen clock the host's system clock (the clock the DVS's packets'
// arrival times are taken with, live_event_collector.h). ROS-free.
#include <dvs_screen_sim/screen_loop/screen_loop_procedure.h>

#include <functional>

namespace dvs_screen_sim
{
namespace screen_loop
{
/// The host's system clock [ns].
int64_t hostNowNs();

class WindowScreen : public LoopScreen
{
public:
  /// `running` is asked before every frame (e.g. ros::ok); empty: always running.
  explicit WindowScreen(GlScreenRenderer& gl, std::function<bool()> running = {});

  /// Measure the refresh period: `frames` black frames, the median interval between swaps.
  /// Returns it (0 when interrupted before two swaps).
  double measureRefreshPeriod(int frames);

  ScreenCanvas& canvas() override { return gl_; }
  double refreshPeriod() const override { return period_; }
  /// Frames are drawn as fast as the swaps allow; a frame's time is when it is drawn, its
  /// `shown` time when its swap returned.
  bool showFrames(double duration, const DrawFrame& draw, const FrameShown& shown) override;

private:
  bool running();

  GlScreenRenderer& gl_;
  std::function<bool()> running_;
  double period_ = 0;
  int64_t frames_ = 0;  ///< refresh counter
};
}  // namespace screen_loop
}  // namespace dvs_screen_sim
