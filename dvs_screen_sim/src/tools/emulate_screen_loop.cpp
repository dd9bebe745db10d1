// emulate_screen_loop: the whole screen-in-the-loop procedure (thesis ch. 3) with the software
// DVS filming a virtual monitor that shows the OpenGL window: alignment from the blinking circle
// grid, the line-grid check, then the scenario's trajectory played on the screen (slowed by the
// time scale) and recorded as a dataset folder in the trajectory's time base.
//   emulate_screen_loop --scenario NAME --out DIR [--config FILE.yaml] [--seed N] [--duration S]
//       [--time-scale F] [--refresh-hz HZ] [--response-ms MS] [--monitor-levels B,W] [--dvs-ypr Y,P,R]
//       [--dvs-distance M] [--window WxH]
// Without $DISPLAY it re-runs itself under xvfb-run.
#include <dvs_driver/checked_write.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/screen_loop/emulated_screen_loop.h>
#include <dvs_screen_sim/screen_loop/line_grid_check.h>
#include <dvs_screen_sim/sim_config.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

using namespace dvs_screen_sim;
using namespace dvs_screen_sim::screen_loop;

namespace
{
void usage(std::ostream& out)
{
  out << "usage: emulate_screen_loop --scenario NAME --out DIR [--config FILE.yaml] [--seed N] [--duration S]\n"
         "         [--time-scale F] [--refresh-hz HZ] [--response-ms MS] [--monitor-levels B,W] [--dvs-ypr Y,P,R]\n"
         "         [--dvs-distance M] [--window WxH]\n"
         "  NAME, --config, --seed, --duration: as for `simulate` (scene, trajectory, camera, event model)\n"
         "  --time-scale F   playback F times slower than the trajectory (default 10)\n"
         "  --refresh-hz HZ  the virtual monitor's refresh rate (default 60)\n"
         "  --response-ms MS the monitor's pixel response time: a new frame fades in linearly over it\n"
         "                   (default 5, a common LCD's grey-to-grey time; 0: an ideal instantaneous screen)\n"
         "  --monitor-levels B,W  intensity of a black and a white screen pixel (default 0.02,0.9)\n"
         "  --dvs-ypr        the DVS's misalignment: yaw,pitch,roll [deg] (default 15,-12,4)\n"
         "  --dvs-distance   DVS to screen [m] (default 0.22)\n"
         "  --window WxH     OpenGL window = monitor pixels (default 1024x768, 0.6 mm pitch)\n"
         "  DIR receives the dataset files of `simulate` (events.txt in trajectory time) and alignment.txt;\n"
         "  groundtruth.txt holds the poses the screen showed, one per refresh, each stamped at the centre of\n"
         "  its display interval plus half the monitor's response time (when its light is half-way)\n";
}

bool parseDouble(const std::string& s, double& v)
{
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0';
}

bool parseTriple(const std::string& s, Eigen::Vector3d& v)
{
  std::stringstream ss(s);
  std::string tok;
  for (int i = 0; i < 3; ++i)
    if (!std::getline(ss, tok, ',') || !parseDouble(tok, v[i]))
      return false;
  return !std::getline(ss, tok, ',');
}
}  // namespace

int main(int argc, char** argv)
{
  std::string scenario, out_dir, config_path;
  std::optional<uint64_t> seed;
  std::optional<double> duration;
  double time_scale = 10.0, refresh_hz = 60.0, distance = 0.22, response_ms = 5.0;
  double black_level = 0.02, white_level = 0.9;
  Eigen::Vector3d ypr(15, -12, 4);
  int win_w = 1024, win_h = 768;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        std::cerr << "emulate_screen_loop: " << arg << " needs a value\n";
        usage(std::cerr);
        std::exit(2);
      }
      return argv[++i];
    };
    double d = 0;
    bool ok = true;
    if (arg == "--scenario")
      scenario = value();
    else if (arg == "--out")
      out_dir = value();
    else if (arg == "--config")
      config_path = value();
    else if (arg == "--seed")
    {
      ok = parseDouble(value(), d) && d >= 0;
      seed = static_cast<uint64_t>(d);
    }
    else if (arg == "--duration")
    {
      ok = parseDouble(value(), d) && d > 0;
      duration = d;
    }
    else if (arg == "--time-scale")
      ok = parseDouble(value(), time_scale) && time_scale > 0;
    else if (arg == "--refresh-hz")
      ok = parseDouble(value(), refresh_hz) && refresh_hz > 0;
    else if (arg == "--response-ms")
      ok = parseDouble(value(), response_ms) && response_ms >= 0;
    else if (arg == "--monitor-levels")
    {
      const std::string v = value();
      char* end = nullptr;
      black_level = std::strtod(v.c_str(), &end);
      ok = end && *end == ',' && parseDouble(end + 1, white_level) && black_level >= 0 && white_level > black_level &&
           white_level <= 1;
    }
    else if (arg == "--dvs-distance")
      ok = parseDouble(value(), distance) && distance > 0;
    else if (arg == "--dvs-ypr")
      ok = parseTriple(value(), ypr);
    else if (arg == "--window")
      ok = std::sscanf(value().c_str(), "%dx%d", &win_w, &win_h) == 2 && win_w > 16 && win_h > 16;
    else if (arg == "-h" || arg == "--help")
    {
      usage(std::cout);
      return 0;
    }
    else
    {
      std::cerr << "emulate_screen_loop: unknown argument '" << arg << "'\n";
      usage(std::cerr);
      return 2;
    }
    if (!ok)
    {
      std::cerr << "emulate_screen_loop: bad value for " << arg << "\n";
      return 2;
    }
  }
  if (scenario.empty() || out_dir.empty())
  {
    usage(std::cerr);
    return 2;
  }
  if (!reexecUnderXvfbIfNoDisplay(argc, argv))
    return 1;
  try
  {
    const SimConfig config = resolveSimConfigFile(scenario, config_path, seed, duration);
    const auto trajectory = makeTrajectory(config);
    WindowConfig wc;
    wc.fullscreen = false;
    wc.width = win_w;
    wc.height = win_h;
    wc.vsync = false;
    GlScreenRenderer gl(wc);

    EmulationConfig ec;
    ec.camera = config.camera;
    ec.T_wall_dvs = EmulationConfig::dvsPoseAimedAt(ypr, Eigen::Vector2d::Zero(), distance);
    ec.monitor.pixel_pitch = 0.0006 * 1024.0 / win_w;
    ec.monitor.top_left = {-0.5 * win_w * ec.monitor.pixel_pitch, 0.5 * win_h * ec.monitor.pixel_pitch};
    ec.monitor.black_level = black_level;
    ec.monitor.white_level = white_level;
    ec.monitor.response_time = response_ms * 1e-3;
    if (ec.monitor.response_time > 1.0 / refresh_hz)
      throw std::invalid_argument("--response-ms must not exceed the refresh period");
    ec.refresh_period = 1.0 / refresh_hz;
    ec.pattern.cols = 7;
    ec.pattern.rows = 5;
    ec.pattern.spacing_vp = {0.085, 0.11};
    ec.pattern.radius_px = 11.0 * win_w / 1024.0;
    ec.model = config.events;
    ec.sampling = config.sampling;
    ec.seed = config.seed;
    EmulatedScreenLoop loop(ec, gl);

    const GridAlignment a = loop.align();
    if (!a.ok)
    {
      std::cerr << "emulate_screen_loop: alignment failed: " << a.reason << "\n";
      return 1;
    }
    std::printf("alignment: H_D residual rms %.3f px, mean %.3f px, max %.3f px over %zu circles\n",
                a.result.residual_dvs_px.rms, a.result.residual_dvs_px.mean, a.result.residual_dvs_px.max,
                a.result.points);
    // The thesis's check (Fig. 3.3): a blinking line grid at 1 m.
    const Pose T_check = Pose::fromWorldCamera(lookingAtWallOrientation(), Eigen::Vector3d(0.0, 0.0, 1.0));
    const auto lines = lineGrid(7, 7, 0.12);
    const auto st = eventLineDistances(loop.showLines(T_check, lines, 0.003, true, 7), ec.camera,
                                       expectedImageLines(ec.camera, T_check, lines));
    std::printf("line grid: mean event distance %.3f px, mean line offset %.3f px (%zu/%zu events)\n",
                st.mean_event_distance, st.mean_line_offset, st.events_used, st.events_total);

    const MotionCheck mc = checkApparentMotion(loop.pipeline(), *trajectory,
                                               motionSamplePoints(config.scene, {}), 0.0, config.duration,
                                               ec.refresh_period, TimeScale{time_scale}, win_w, win_h);
    const std::string warn = motionWarning(mc);
    if (!warn.empty())
      std::fprintf(stderr, "warning: %s\n", warn.c_str());
    std::printf("apparent motion: max %.2f screen px per refresh at time scale %.2f\n", mc.max_px_per_refresh,
                time_scale);

    const std::clock_t c0 = std::clock();
    dvs_calibration::Trajectory gt;  // the poses the screen showed, each stamped when the DVS sees it (centre of its display interval + half the response time)
    dvs_driver::EventVector events =
        loop.playTrajectory(config.scene, *trajectory, config.duration, TimeScale{time_scale}, &gt);
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    for (auto& e : events)
      e.t_ns += config.time_offset_ns;
    std::filesystem::create_directories(out_dir);
    for (auto& sp : gt)
      sp.t += static_cast<double>(config.time_offset_ns) * 1e-9;
    writeDatasetWithoutEvents(out_dir, config, gt);
    EventsTextStream ev(out_dir + "/events.txt");
    ev.write(events);
    ev.close();
    dvs_driver::CheckedFileWriter report(out_dir + "/alignment.txt");
    std::ostream& rep = report.stream();
    rep << "# screen-in-the-loop emulation (thesis ch. 3): DVS yaw,pitch,roll " << ypr.transpose() << " deg at "
        << distance << " m\n# H_D (ideal DVS px -> viewport)\n"
        << a.result.H_D << "\n# H (viewport correction, Eq. 3.14)\n"
        << a.result.H << "\nresidual_rms_px " << a.result.residual_dvs_px.rms << "\nline_grid_mean_event_distance_px "
        << st.mean_event_distance << "\nline_grid_mean_line_offset_px " << st.mean_line_offset << "\ntime_scale "
        << time_scale << "\nrefresh_hz " << refresh_hz << "\nresponse_ms " << response_ms << "\nmax_screen_px_per_refresh " << mc.max_px_per_refresh
        << "\n";
    report.commit();  // throws WriteError naming the file (full disk, missing folder)
    std::printf("%zu events over %.3f s of trajectory (%.1f s of screen time, %.1f s CPU) -> %s\n", events.size(),
                config.duration, config.duration * time_scale, cpu, out_dir.c_str());
  }
  catch (const std::exception& e)
  {
    std::cerr << "emulate_screen_loop: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
