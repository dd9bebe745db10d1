#include <dvs_screen_sim/screen_loop/virtual_monitor.h>

#include <stdexcept>

namespace dvs_screen_sim
{
namespace screen_loop
{
SceneImage makeVirtualMonitor(GlScreenRenderer& gl, const MonitorGeometry& g, double refresh_period,
                              FrameDrawer draw_frame)
{
  if (!(refresh_period > 0))
    throw std::invalid_argument("virtual monitor: refresh_period must be positive");
  if (!(g.pixel_pitch > 0))
    throw std::invalid_argument("virtual monitor: pixel_pitch must be positive");
  SceneImage im;
  im.name = "virtual_monitor";
  im.file = "(OpenGL window read back)";
  im.width = gl.width();
  im.height = gl.height();
  im.top_left = g.top_left;
  im.size = Eigen::Vector2d(im.width * g.pixel_pitch, im.height * g.pixel_pitch);
  im.texels.assign(static_cast<size_t>(im.width) * im.height, static_cast<float>(g.black_level));
  im.update_period = refresh_period;
  im.response_time = g.response_time;
  GlScreenRenderer* renderer = &gl;
  const float black = static_cast<float>(g.black_level), span = static_cast<float>(g.white_level - g.black_level);
  im.update = [renderer, draw_frame, black, span](int64_t frame, std::vector<float>& texels) {
    draw_frame(frame, *renderer);
    renderer->readBackBuffer(texels);
    for (auto& v : texels)
      v = black + span * v;
    renderer->swap();
  };
  return im;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
