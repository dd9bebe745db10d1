#include <dvs_screen_sim/screen_loop/emulated_screen_loop.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dvs_screen_sim
{
namespace screen_loop
{
struct EmulatedScreenLoop::Program
{
  enum class Mode
  {
    Blank,
    Circles,
    Lines,
    Scene
  };
  Mode mode = Mode::Blank;
  AlignmentPattern pattern;
  ProjectionPipeline pipeline;
  // Lines
  Pose T_world_virtual;
  std::vector<WorldLine> lines;
  double line_width = 0.003;
  bool corrected = true;
  // Scene playback
  const Scene* scene = nullptr;
  const Trajectory* trajectory = nullptr;
  int64_t first_frame = 0;
  double refresh_period = 1.0 / 60;
  TimeScale time_scale;
  PoseTrajectory* shown = nullptr;  ///< receives the displayed poses when set
  double seen_delay = 0;            ///< screen time from a frame's nominal time to its light being half-way (half the response time)

  void draw(int64_t frame, GlScreenRenderer& gl)
  {
    switch (mode)
    {
      case Mode::Blank:
        gl.clear(0.0);
        return;
      case Mode::Circles:
        gl.clear(pattern.off_intensity);
        if ((frame / pattern.blink_frames) % 2 == 0)
          gl.drawViewportDiscs(patternCentresViewport(pattern), pattern.radius_px, pattern.on_intensity);
        return;
      case Mode::Lines:
        gl.clear(0.0);
        if (frame % 2 == 0)
        {
          gl.setMatrices(corrected ? pipeline.correctedProjection() : pipeline.projection(), viewMatrix(T_world_virtual));
          gl.drawWorldLines(lines, line_width, 1.0);
        }
        return;
      case Mode::Scene:
      {
        // Sample and hold: frame f stays on screen for one refresh, trajectory time
        // [(f - first) dt, (f - first + 1) dt) with dt = refresh_period / time scale. It shows the
        // pose at the centre of that interval: the DVS's events of a frame switch fill the band
        // swept between two consecutive displayed poses, so they are centred on the switch time.
        const double t_traj =
            std::max(0.0, time_scale.trajectoryTime((static_cast<double>(frame - first_frame) + 0.5) * refresh_period));
        const Pose pose = trajectory->poseAt(t_traj);
        gl.clear(scene->background_reflectance);
        gl.setMatrices(pipeline.correctedProjection(), viewMatrix(pose));
        gl.drawScenePolygons(*scene, t_traj);
        // The DVS sees the frame once the monitor's light has moved half-way to it (half its
        // response time after the switch): the ground truth is stamped then.
        if (shown && frame >= first_frame)
          shown->push_back(
              {time_scale.trajectoryTime((static_cast<double>(frame - first_frame) + 0.5) * refresh_period + seen_delay),
               pose});
        return;
      }
    }
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
  return Pose{Eigen::Vector3d(aim.x(), aim.y(), 0.0) - distance / std::abs(axis.z()) * axis, q};
}

EmulatedScreenLoop::EmulatedScreenLoop(const EmulationConfig& config, GlScreenRenderer& gl)
  : config_(config), gl_(gl), program_(std::make_shared<Program>())
{
  config_.pattern.validate();
  program_->pattern = config_.pattern;
  program_->pipeline = ProjectionPipeline(config_.camera);
  program_->refresh_period = config_.refresh_period;
  Scene physical;
  physical.background_reflectance = config_.monitor.black_level;
  auto program = program_;
  physical.images.push_back(makeVirtualMonitor(gl_, config_.monitor, config_.refresh_period,
                                               [program](int64_t f, GlScreenRenderer& g) { program->draw(f, g); }));
  physical.finalize();
  still_ = std::make_unique<StaticTrajectory>(config_.T_wall_dvs);
  sim_ = std::make_unique<EventSimulator>(config_.camera, physical, config_.model, config_.sampling, config_.seed);
  sim_->start(*still_, 0.0);
}

ProjectionPipeline& EmulatedScreenLoop::pipeline()
{
  return program_->pipeline;
}

int64_t EmulatedScreenLoop::alignToRefresh()
{
  const int64_t next = static_cast<int64_t>(std::floor(sim_->currentTime() / config_.refresh_period + 1e-9)) + 1;
  dvs_driver::EventVector discard;
  sim_->advanceTo(next * config_.refresh_period, discard);
  return next;
}

GridAlignment EmulatedScreenLoop::align()
{
  program_->mode = Program::Mode::Circles;
  const int64_t f0 = alignToRefresh();
  dvs_driver::EventVector events;
  sim_->advanceTo((f0 + config_.alignment_frames) * config_.refresh_period, events);
  dvs_calibration::EventWindow window(config_.camera.width(), config_.camera.height());
  window.reset(static_cast<int64_t>(std::llround((f0 + 1) * config_.refresh_period * 1e9)),
               static_cast<int64_t>(std::llround((f0 + config_.alignment_frames) * config_.refresh_period * 1e9)));
  for (const auto& e : events)
    if (e.t_ns >= window.beginNs())
      window.add(e);
  GridAlignment a = alignFromEvents(window, config_.camera, program_->pipeline, config_.pattern, config_.detector);
  if (a.ok)
    program_->pipeline.setCorrection(a.result.H);
  return a;
}

dvs_driver::EventVector EmulatedScreenLoop::showLines(const Pose& T_world_virtual, const std::vector<WorldLine>& lines,
                                                      double width, bool corrected, int frames)
{
  program_->mode = Program::Mode::Lines;
  program_->T_world_virtual = T_world_virtual;
  program_->lines = lines;
  program_->line_width = width;
  program_->corrected = corrected;
  const int64_t f0 = alignToRefresh();
  dvs_driver::EventVector events, out;
  sim_->advanceTo((f0 + frames) * config_.refresh_period, events);
  const auto t_first = static_cast<int64_t>(std::llround((f0 + 1) * config_.refresh_period * 1e9));
  for (const auto& e : events)
    if (e.t_ns >= t_first)
      out.push_back(e);
  return out;
}

dvs_driver::EventVector EmulatedScreenLoop::playTrajectory(const Scene& scene, const Trajectory& trajectory,
                                                           double duration, const TimeScale& time_scale,
                                                           PoseTrajectory* shown)
{
  time_scale.validate();
  // One refresh showing the start pose, so the playback starts from a settled screen.
  program_->mode = Program::Mode::Scene;
  program_->scene = &scene;
  program_->trajectory = &trajectory;
  program_->time_scale = time_scale;
  program_->shown = shown;
  program_->seen_delay = 0.5 * config_.monitor.response_time;
  if (shown)
    shown->clear();
  program_->first_frame = std::numeric_limits<int64_t>::max() / 4;  // start pose until armed
  const int64_t f_settle = alignToRefresh();
  program_->first_frame = f_settle + 1;
  dvs_driver::EventVector discard;
  sim_->advanceTo((f_settle + 1) * config_.refresh_period, discard);
  const double t0 = (f_settle + 1) * config_.refresh_period;
  const int64_t t0_ns = static_cast<int64_t>(std::llround(t0 * 1e9));
  dvs_driver::EventVector events;
  sim_->advanceTo(t0 + time_scale.playbackTime(duration), events);
  sim_->flush(events);
  dvs_driver::EventVector out;
  out.reserve(events.size());
  for (auto e : events)
  {
    if (e.t_ns < t0_ns)
      continue;
    e.t_ns = time_scale.rescaleStampNs(e.t_ns - t0_ns);
    out.push_back(e);
  }
  program_->mode = Program::Mode::Blank;
  program_->shown = nullptr;
  return out;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
