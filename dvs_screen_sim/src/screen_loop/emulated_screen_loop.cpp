#include <dvs_screen_sim/screen_loop/emulated_screen_loop.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dvs_screen_sim
{
namespace screen_loop
{
/// What the virtual monitor's frames show: the current showFrames() call's drawer (black between
/// calls).
struct EmulatedScreen::Phase
{
  const DrawFrame* draw = nullptr;
  const FrameShown* shown = nullptr;
  int64_t first = 0;  ///< frame index of the call's first frame
  double period = 1.0 / 60;

  void frame(int64_t f, GlScreenRenderer& gl) const
  {
    if (!draw)
    {
      gl.clear(0.0);
      return;
    }
    Frame fr;
    fr.index = f;
    fr.k = f - first;
    fr.start_ns = static_cast<int64_t>(std::llround(static_cast<double>(f) * period * 1e9));
    fr.t = static_cast<double>(f - first) * period;
    (*draw)(fr, gl);
    // The virtual monitor shows it from its refresh on.
    if (shown && *shown)
      (*shown)(fr, fr.start_ns);
  }
};

LineDistanceStats referenceLineGridDistances(const EmulationConfig& config, const Pose& T_world_virtual, int nx, int ny,
                                             double spacing, double width, int frames)
{
  IntensityModulation blink;
  blink.type = IntensityModulation::Type::Square;
  blink.frequency_hz = 0.5 / config.refresh_period;
  blink.low = config.monitor.black_level;
  blink.high = config.monitor.white_level;
  const Scene direct = lineGridScene(nx, ny, spacing, width, blink, config.monitor.black_level);
  const dvs_driver::EventVector events =
      simulateEvents(config.camera, direct, StaticTrajectory(T_world_virtual), 0.0, frames * config.refresh_period,
                     config.model, config.sampling, config.seed);
  dvs_driver::EventVector used;
  const auto t_first = static_cast<int64_t>(std::llround(config.refresh_period * 1e9));
  for (const auto& e : events)
    if (e.t_ns >= t_first)
      used.push_back(e);
  return eventLineDistances(used, config.camera,
                            expectedImageLines(config.camera, T_world_virtual, lineGrid(nx, ny, spacing)));
}

Pose EmulationConfig::dvsPoseAimedAt(const Eigen::Vector3d& ypr_deg, const Eigen::Vector2d& aim, double distance)
{
  const Eigen::Quaterniond q = orientationFromYawPitchRollDeg(ypr_deg);
  const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitZ();
  return Pose::fromWorldCamera(q, Eigen::Vector3d(Eigen::Vector3d(aim.x(), aim.y(), 0.0) - distance / std::abs(axis.z()) * axis));
}

EmulatedScreen::EmulatedScreen(const EmulationConfig& config, GlScreenRenderer& gl)
  : config_(config), gl_(gl), phase_(std::make_shared<Phase>())
{
  phase_->period = config_.refresh_period;
  Scene physical;
  physical.background_reflectance = config_.monitor.black_level;
  auto phase = phase_;
  physical.images.push_back(makeVirtualMonitor(gl_, config_.monitor, config_.refresh_period,
                                               [phase](int64_t f, GlScreenRenderer& g) { phase->frame(f, g); }));
  physical.finalize();
  still_ = std::make_unique<StaticTrajectory>(config_.T_wall_dvs);
  sim_ = std::make_unique<EventSimulator>(config_.camera, physical, config_.model, config_.sampling, config_.seed);
  sim_->start(*still_, 0.0);
}

void EmulatedScreen::advanceTo(double t)
{
  released_.clear();
  sim_->advanceTo(t, released_);
  if (keeping_)
    for (const auto& e : released_)
      if (e.t_ns >= keep_from_ns_)
        kept_.push_back(e);
}

bool EmulatedScreen::showFrames(double duration, const DrawFrame& draw, const FrameShown& shown)
{
  const double p = config_.refresh_period;
  // Content switches at refreshes: the first frame is the next refresh's.
  const int64_t first = static_cast<int64_t>(std::floor(sim_->currentTime() / p + 1e-9)) + 1;
  phase_->draw = &draw;
  phase_->shown = &shown;
  phase_->first = first;
  advanceTo(static_cast<double>(first) * p);
  // A whole number of refreshes ends exactly on a refresh (whose frame is still this call's).
  const double n = duration / p;
  const double whole = std::round(n);
  advanceTo(std::abs(n - whole) < 1e-9 ? static_cast<double>(first + static_cast<int64_t>(whole)) * p
                                       : static_cast<double>(first) * p + duration);
  phase_->draw = nullptr;
  phase_->shown = nullptr;
  return true;
}

void EmulatedScreen::keepFrom(int64_t from_dvs_ns)
{
  keeping_ = true;
  keep_from_ns_ = from_dvs_ns;
  kept_.clear();
}

void EmulatedScreen::drain()
{
  released_.clear();
  sim_->flush(released_);
  if (keeping_)
    for (const auto& e : released_)
      if (e.t_ns >= keep_from_ns_)
        kept_.push_back(e);
}

dvs_driver::EventVector EmulatedScreen::takeKept()
{
  keeping_ = false;
  dvs_driver::EventVector out;
  out.swap(kept_);
  return out;
}

ProcedureConfig EmulatedScreenLoop::procedureConfig(const EmulationConfig& config)
{
  if (config.alignment_frames < 2)
    throw std::invalid_argument("EmulationConfig.alignment_frames must be >= 2 (the first one is skipped)");
  ProcedureConfig pc;
  pc.pattern = config.pattern;
  pc.detector = config.detector;
  pc.alignment_settle = config.refresh_period;
  pc.alignment_duration = (config.alignment_frames - 1) * config.refresh_period;
  pc.alignment_attempts = 1;
  pc.response_time = config.monitor.response_time;
  pc.settle_frames = 1;
  return pc;
}

EmulatedScreenLoop::EmulatedScreenLoop(const EmulationConfig& config, GlScreenRenderer& gl)
  : screen_(config, gl), procedure_(procedureConfig(config), config.camera, screen_, screen_)
{
}

dvs_driver::EventVector EmulatedScreenLoop::playTrajectory(const Scene& scene, const Trajectory& trajectory,
                                                           double duration, const TimeScale& time_scale,
                                                           dvs_calibration::Trajectory* shown)
{
  Playback p = procedure_.play(scene, trajectory, duration, time_scale);
  if (shown)
    *shown = std::move(p.shown);
  return std::move(p.events);
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
