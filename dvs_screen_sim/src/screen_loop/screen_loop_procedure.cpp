#include <dvs_screen_sim/screen_loop/screen_loop_procedure.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>

namespace dvs_screen_sim
{
namespace screen_loop
{
void ProcedureConfig::validate() const
{
  try
  {
    pattern.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw std::invalid_argument(std::string("pattern: ") + e.what());
  }
  if (!(alignment_settle >= 0))
    throw std::invalid_argument("alignment_settle must be >= 0 s");
  if (!(alignment_duration > 0))
    throw std::invalid_argument("alignment_duration must be > 0 s");
  if (alignment_attempts < 1)
    throw std::invalid_argument("alignment_attempts must be >= 1");
  if (!(max_alignment_residual > 0))
    throw std::invalid_argument("max_alignment_residual must be positive");
  if (!(response_time >= 0 && response_time < 0.1))
    throw std::invalid_argument("response_time must be in [0, 0.1) s");
  if (settle_frames < 0)
    throw std::invalid_argument("settle_frames must be >= 0");
}

ScreenLoopProcedure::ScreenLoopProcedure(const ProcedureConfig& config, const dvs_calibration::CameraModel& camera,
                                         LoopScreen& screen, LoopEventSource& events, ProcedureLog log)
  : config_(config), camera_(camera), screen_(screen), events_(events), log_(std::move(log)), pipeline_(camera)
{
  config_.validate();
}

void ScreenLoopProcedure::log(LogLevel level, const std::string& message) const
{
  if (log_)
    log_(level, message);
  else if (level != LogLevel::Info)
    std::cerr << "screen_loop: " << message << "\n";
}

double ScreenLoopProcedure::period() const
{
  const double p = screen_.refreshPeriod();
  return p > 0 ? p : 1.0 / 60;
}

GridAlignment ScreenLoopProcedure::align()
{
  const AlignmentPattern& pattern = config_.pattern;
  const Points2d centres = patternCentresViewport(pattern);
  GridAlignment a;
  a.reason = "no alignment attempt ran";
  char buf[256];
  for (int attempt = 0; attempt < config_.alignment_attempts; ++attempt)
  {
    bool keeping = false;
    int64_t from = 0;
    const bool ran = screen_.showFrames(
        config_.alignment_settle + config_.alignment_duration,
        [&](const Frame& f, ScreenCanvas& gl) {
          // The first frames (the screen switching on) do not count.
          if (!keeping && f.t >= config_.alignment_settle - 1e-9)
          {
            from = events_.dvsTimeNs(f.start_ns);
            events_.keepFrom(from);
            keeping = true;
          }
          gl.clear(pattern.off_intensity);
          if ((f.index / pattern.blink_frames) % 2 == 0)
            gl.drawViewportDiscs(centres, pattern.radius_px, pattern.on_intensity);
        },
        {});
    const dvs_driver::EventVector events = events_.takeKept();
    if (!ran)
    {
      a.ok = false;
      a.reason = "interrupted";
      return a;
    }
    dvs_calibration::EventWindow window(camera_.width(), camera_.height());
    window.reset(from, events.empty() ? from : events.back().t_ns + 1);
    for (const auto& e : events)
      window.add(e);
    a = alignFromEvents(window, camera_, pipeline_, pattern, config_.detector);
    if (!a.ok)
    {
      std::snprintf(buf, sizeof(buf), "alignment attempt %d: %s (%zu events)", attempt + 1, a.reason.c_str(),
                    window.numEvents());
      log(LogLevel::Warn, buf);
      continue;
    }
    std::snprintf(buf, sizeof(buf), "alignment residual %.3f px rms, %.3f px max over %zu circles",
                  a.result.residual_dvs_px.rms, a.result.residual_dvs_px.max, a.result.points);
    log(LogLevel::Info, buf);
    if (a.result.residual_dvs_px.rms > config_.max_alignment_residual)
    {
      std::snprintf(buf, sizeof(buf), "residual above max_alignment_residual (%.3f px): retrying",
                    config_.max_alignment_residual);
      log(LogLevel::Warn, buf);
      a.ok = false;
      a.reason = buf;
      continue;
    }
    pipeline_.setCorrection(a.result.H);
    return a;
  }
  std::snprintf(buf, sizeof(buf),
                "alignment failed after %d attempts: is the DVS looking at the screen, in focus, and does the grid "
                "lie inside its view (pattern)?",
                config_.alignment_attempts);
  log(LogLevel::Error, buf);
  return a;
}

dvs_driver::EventVector ScreenLoopProcedure::showLines(const Pose& T_world_virtual, const std::vector<WorldLine>& lines,
                                                       double width, bool corrected, int frames)
{
  if (frames < 2)
    throw std::invalid_argument("showLines: frames must be >= 2 (the first one is skipped)");
  const Eigen::Matrix4d view = viewMatrix(T_world_virtual);
  screen_.showFrames(frames * period(),
                     [&](const Frame& f, ScreenCanvas& gl) {
                       if (f.k == 1)
                         events_.keepFrom(events_.dvsTimeNs(f.start_ns));
                       gl.clear(0.0);
                       if (f.index % 2 == 0)
                       {
                         gl.setMatrices(corrected ? pipeline_.correctedProjection() : pipeline_.projection(), view);
                         gl.drawWorldLines(lines, width, 1.0);
                       }
                     },
                     {});
  return events_.takeKept();
}

MotionCheck ScreenLoopProcedure::checkMotion(const Scene& scene, const Trajectory& trajectory, double duration,
                                             const TimeScale& time_scale) const
{
  const ScreenCanvas& gl = screen_.canvas();
  return checkApparentMotion(pipeline_, trajectory, motionSamplePoints(scene, {}), 0.0, duration, period(), time_scale,
                             gl.width(), gl.height());
}

Playback ScreenLoopProcedure::play(const Scene& scene, const Trajectory& trajectory, double duration,
                                   const TimeScale& time_scale, const std::function<void(const StampedPose&)>& live,
                                   bool keep_events)
{
  time_scale.validate();
  if (!(duration > 0))
    throw std::invalid_argument("play: duration must be > 0");
  Playback out;
  const double hold = period();
  const int settle = config_.settle_frames;
  const double t_settle = settle * hold;
  // The DVS sees a frame half a refresh after it is shown (the centre of its display interval:
  // its events of a frame switch fill the band swept between two displayed poses) plus half the
  // monitor's response time (when the light is half-way).
  const double seen_delay = 0.5 * hold + 0.5 * config_.response_time;
  const auto seen_delay_ns = static_cast<int64_t>(std::llround(seen_delay * 1e9));
  if (!events_.clockValid())
    log(LogLevel::Warn, "no events received yet: ground truth stamped with the host clock");
  bool started = false;
  Pose pose;  // the pose of the frame being drawn
  const Eigen::Matrix4d& projection = pipeline_.correctedProjection();
  auto draw = [&](const Frame& f, ScreenCanvas& gl) {
    if (f.k == settle && !started)
    {
      out.start_dvs_ns = events_.dvsTimeNs(f.start_ns);
      if (keep_events)
        events_.keepFrom(out.start_dvs_ns);
      started = true;
    }
    // Sample and hold: a frame shows the pose at the centre of its display interval (settling
    // frames: the start pose).
    const double t_traj = f.k < settle ? 0.0 : std::max(0.0, time_scale.trajectoryTime(f.t - t_settle + 0.5 * hold));
    pose = trajectory.poseAt(t_traj);
    gl.clear(scene.background_reflectance);
    gl.setMatrices(projection, viewMatrix(pose));
    gl.drawScenePolygons(scene, t_traj);
  };
  auto shown = [&](const Frame& f, int64_t shown_ns) {
    if (f.k < settle)
      return;
    const int64_t seen_dvs_ns = events_.dvsTimeNs(shown_ns) + seen_delay_ns;
    if (live)
      live({seen_dvs_ns * 1e-9, pose});
    // Rescale: trajectory time since the playback's start.
    out.shown.push_back(
        {time_scale.trajectoryTime(1e-9 * static_cast<double>(events_.dvsTimeNs(shown_ns) - out.start_dvs_ns) +
                                   seen_delay),
         pose});
  };
  out.completed = screen_.showFrames(t_settle + time_scale.playbackTime(duration), draw, shown);
  if (keep_events)
    events_.drain();
  dvs_driver::EventVector events = events_.takeKept();
  if (!keep_events)
    return out;
  // Rescale: event time stamps back to trajectory time since the playback's start.
  out.events.reserve(events.size());
  for (auto e : events)
  {
    if (e.t_ns < out.start_dvs_ns)
      continue;
    e.t_ns = time_scale.rescaleStampNs(e.t_ns - out.start_dvs_ns);
    out.events.push_back(e);
  }
  return out;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
