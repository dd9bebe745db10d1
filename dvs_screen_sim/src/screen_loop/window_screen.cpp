#include <dvs_screen_sim/screen_loop/window_screen.h>

#include <chrono>

namespace dvs_screen_sim
{
namespace screen_loop
{
int64_t hostNowNs()
{
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

WindowScreen::WindowScreen(GlScreenRenderer& gl, std::function<bool()> running)
  : gl_(gl), running_(std::move(running))
{
}

bool WindowScreen::running()
{
  return (!running_ || running_()) && gl_.pollEvents();
}

double WindowScreen::measureRefreshPeriod(int frames)
{
  RefreshPeriodEstimator refresh;
  for (int i = 0; i < frames && (!running_ || running_()); ++i)
  {
    gl_.clear(0.0);
    gl_.swap();
    ++frames_;
    refresh.addSwapTime(hostNowNs() * 1e-9);
  }
  period_ = refresh.period();
  return period_;
}

bool WindowScreen::showFrames(double duration, const DrawFrame& draw, const FrameShown& shown)
{
  const int64_t t0 = hostNowNs();
  for (int64_t k = 0;; ++k)
  {
    if (!running())
      return false;
    Frame f;
    f.start_ns = hostNowNs();
    f.t = static_cast<double>(f.start_ns - t0) * 1e-9;
    if (f.t > duration)
      return true;
    f.index = frames_++;
    f.k = k;
    draw(f, gl_);
    gl_.swap();
    if (shown)
      shown(f, hostNowNs());
  }
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
