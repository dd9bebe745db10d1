// Test helper node: a software DVS filming the X screen. Every refresh period it grabs a region
// of the root window (XGetImage) as the content of a virtual monitor on the wall, and the event
// simulator (a still DVS at a misaligned pose in front of it) runs in wall-clock time, publishing
// dvs/events stamped with the wall clock. Used by the screen_loop node's end-to-end rostest.
#include <dvs_driver/event_bag_io.h>
#include <dvs_msgs/EventArray.h>
#include <dvs_screen_sim/event_simulator.h>
#include <dvs_screen_sim/screen_loop/emulated_screen_loop.h>
#include <ros/ros.h>

#include <X11/Xlib.h>
#include <X11/Xutil.h>

#include <unistd.h>

#include <chrono>
#include <thread>

using namespace dvs_screen_sim;

namespace
{
int onDisplayLost(Display*)
{
  _exit(0);  // the test's X server went away: the test is over
}
}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "fake_screen_dvs");
  ros::NodeHandle nh, pnh("~");
  const int w = pnh.param("region_width", 640), h = pnh.param("region_height", 480);
  const double pitch = pnh.param("pixel_pitch", 0.00096);
  const double refresh = pnh.param("refresh_period", 1.0 / 60);
  std::vector<double> ypr = {15, -12, 4};
  pnh.getParam("ypr_deg", ypr);
  XSetIOErrorHandler(&onDisplayLost);
  Display* dpy = nullptr;
  for (int i = 0; i < 50 && !(dpy = XOpenDisplay(nullptr)); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (!dpy)
  {
    ROS_FATAL("fake_screen_dvs: cannot open the X display");
    return 1;
  }
  const Window root = DefaultRootWindow(dpy);
  SceneImage im;
  im.name = "x_screen";
  im.width = w;
  im.height = h;
  im.top_left = {-0.5 * w * pitch, 0.5 * h * pitch};
  im.size = {w * pitch, h * pitch};
  im.texels.assign(static_cast<size_t>(w) * h, 0.02f);
  im.update_period = refresh;
  im.update = [dpy, root, w, h](int64_t, std::vector<float>& texels) {
    XImage* img = XGetImage(dpy, root, 0, 0, static_cast<unsigned>(w), static_cast<unsigned>(h), AllPlanes, ZPixmap);
    if (!img)
      return;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
      {
        const unsigned long p = XGetPixel(img, x, y);
        const double g = ((p & img->green_mask) >> 8 & 0xff) / 255.0;
        texels[static_cast<size_t>(y) * w + x] = static_cast<float>(0.02 + 0.88 * g);
      }
    XDestroyImage(img);
  };
  Scene scene;
  scene.background_reflectance = 0.02;
  scene.images.push_back(im);
  scene.finalize();
  const auto camera = dvs_calibration::CameraModel::dvs128();
  const StaticTrajectory still(
      screen_loop::EmulationConfig::dvsPoseAimedAt({ypr[0], ypr[1], ypr[2]}, Eigen::Vector2d::Zero(), 0.22));
  EventSimulator sim(camera, scene, EventModelConfig(), SamplingConfig(), 1);
  const auto t0 = std::chrono::system_clock::now();
  const int64_t t0_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t0.time_since_epoch()).count();
  sim.start(still, 0.0, t0_ns);
  ros::Publisher pub = nh.advertise<dvs_msgs::EventArray>("dvs/events", 100);
  dvs_driver::EventVector events;
  while (ros::ok())
  {
    const double t = std::chrono::duration<double>(std::chrono::system_clock::now() - t0).count();
    events.clear();
    sim.advanceTo(std::floor(t * 1000.0) / 1000.0, events);
    if (!events.empty())
      pub.publish(dvs_driver::toMessage(events.data(), events.data() + events.size(), 128, 128));
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  XCloseDisplay(dpy);
  return 0;
}
