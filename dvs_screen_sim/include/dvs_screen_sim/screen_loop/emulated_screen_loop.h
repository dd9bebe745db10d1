#pragma once
// The whole screen-in-the-loop procedure (screen_loop_procedure.h, the code the screen_loop
// node runs) with the software DVS standing in for the real one (issue 7's "verification without
// hardware", and a way to make "screen in the loop" datasets without a sensor): the OpenGL
// window, read back every refresh, is a virtual monitor on the wall of dvs_screen_sim's world,
// filmed by the software DVS at a misaligned pose.
//   1. align():   the blinking circle grid, detected in the events -> H (Eq. 3.11-3.14)
//   2. showLines(): a blinking line grid through the corrected (or uncorrected) pipeline
//   3. playTrajectory(): the virtual scene along a trajectory, slowed by a time scale; the
//      events' time stamps are mapped back to trajectory time.
// Simulated time only advances (one EventSimulator); the screen switches content at refreshes.
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/event.h>
#include <dvs_screen_sim/event_simulator.h>
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/screen_loop/gl_screen_renderer.h>
#include <dvs_screen_sim/screen_loop/grid_alignment.h>
#include <dvs_screen_sim/screen_loop/line_grid_check.h>
#include <dvs_screen_sim/screen_loop/screen_loop_procedure.h>
#include <dvs_screen_sim/screen_loop/screen_timing.h>
#include <dvs_screen_sim/screen_loop/virtual_monitor.h>
#include <dvs_screen_sim/trajectory.h>

#include <memory>

namespace dvs_screen_sim
{
namespace screen_loop
{
struct EmulationConfig
{
  dvs_calibration::CameraModel camera;       ///< the (software) DVS, also used for the pipeline
  Pose T_wall_dvs;                           ///< where the DVS stands in front of the monitor
  MonitorGeometry monitor;                   ///< the monitor on the wall (its pixels = the window's)
  double refresh_period = 1.0 / 60.0;        ///< [s]
  AlignmentPattern pattern;
  GridAlignmentConfig detector;
  EventModelConfig model;
  SamplingConfig sampling;
  uint64_t seed = 0;
  int alignment_frames = 7;                  ///< refreshes shown (the first one is not used)
  /// The DVS aimed at `aim` on the wall from `distance` metres (along the optical axis's normal
  /// component) with orientation yaw/pitch/roll (degrees, relative to looking at the wall).
  static Pose dvsPoseAimedAt(const Eigen::Vector3d& ypr_deg, const Eigen::Vector2d& aim, double distance);
};

/// The pure-software reference of the line-grid check: the same DVS at the virtual camera's
/// pose looking at an nx x ny grid of lines (`spacing`, `width` m, at the origin of the wall)
/// blinking at half the refresh rate between black_level and white_level, directly (no screen),
/// for `frames` refreshes (the first is skipped). Its per-event distance is the floor set by the
/// pixel grid.
LineDistanceStats referenceLineGridDistances(const EmulationConfig& config, const Pose& T_world_virtual, int nx, int ny,
                                             double spacing, double width, int frames);

/// The screen in the loop emulated: the OpenGL window, read back at every refresh, is the
/// virtual monitor on the wall; the software DVS (a still EventSimulator at T_wall_dvs) films
/// it. It is both the procedure's screen and its event source; simulated time only advances
/// while frames are shown, and the screen clock is the simulation time (so is the DVS's).
class EmulatedScreen : public LoopScreen, public LoopEventSource
{
public:
  /// `gl` is the window shown on the virtual monitor (its size = the monitor's pixels).
  EmulatedScreen(const EmulationConfig& config, GlScreenRenderer& gl);

  // LoopScreen
  ScreenCanvas& canvas() override { return gl_; }
  double refreshPeriod() const override { return config_.refresh_period; }
  bool showFrames(double duration, const DrawFrame& draw, const FrameShown& shown) override;

  // LoopEventSource: the software DVS stamps events with the simulation time.
  int64_t dvsTimeNs(int64_t screen_ns) const override { return screen_ns; }
  bool clockValid() const override { return true; }
  void keepFrom(int64_t from_dvs_ns) override;
  void drain() override;
  dvs_driver::EventVector takeKept() override;

  const EventSimulator& simulator() const { return *sim_; }

private:
  struct Phase;
  /// Advance to `t` [s], passing the released events to the keep filter.
  void advanceTo(double t);

  EmulationConfig config_;
  GlScreenRenderer& gl_;
  std::shared_ptr<Phase> phase_;  ///< what the virtual monitor's frames draw (shared with its update)
  std::unique_ptr<StaticTrajectory> still_;
  std::unique_ptr<EventSimulator> sim_;
  dvs_driver::EventVector released_, kept_;
  bool keeping_ = false;
  int64_t keep_from_ns_ = 0;
};

/// The whole procedure (screen_loop_procedure.h) on the emulated screen: what
/// emulate_screen_loop, benchmark_screen_loop and the tests run.
class EmulatedScreenLoop
{
public:
  /// `gl` is the window shown on the virtual monitor (its size = the monitor's pixels).
  EmulatedScreenLoop(const EmulationConfig& config, GlScreenRenderer& gl);

  /// Phase 1: blink the circle grid for alignment_frames refreshes, detect, align. On success the
  /// pipeline's correction is set.
  GridAlignment align() { return procedure_.align(); }

  /// Blink world lines (drawn `width` m wide at the virtual pose) for `frames` refreshes; returns
  /// the events after the first refresh (simulation time base).
  dvs_driver::EventVector showLines(const Pose& T_world_virtual, const std::vector<WorldLine>& lines, double width,
                                    bool corrected, int frames)
  {
    return procedure_.showLines(T_world_virtual, lines, width, corrected, frames);
  }

  /// Play `scene` along `trajectory` from trajectory time 0 to `duration` (after one refresh
  /// showing the start pose). Each refresh holds one frame on the screen for dt = refresh_period
  /// / time_scale of trajectory time, showing the pose at the centre of its display interval
  /// (sample and hold centred on the trajectory: the events of a frame switch, which fill the
  /// band swept between two displayed poses, are then centred on the switch time). Returns the
  /// events in the trajectory's time base (time stamps rescaled, starting at 0); `shown`
  /// (optional) receives the displayed poses, each stamped when the DVS sees it (the centre of
  /// its display interval plus half the monitor's response time), in trajectory time.
  dvs_driver::EventVector playTrajectory(const Scene& scene, const Trajectory& trajectory, double duration,
                                         const TimeScale& time_scale, dvs_calibration::Trajectory* shown = nullptr);

  ProjectionPipeline& pipeline() { return procedure_.pipeline(); }
  ScreenLoopProcedure& procedure() { return procedure_; }
  const EventSimulator& simulator() const { return screen_.simulator(); }

  /// The procedure's settings of the emulation: alignment over alignment_frames refreshes (the
  /// first one skipped), one attempt, one settling refresh before the playback.
  static ProcedureConfig procedureConfig(const EmulationConfig& config);

private:
  EmulatedScreen screen_;
  ScreenLoopProcedure procedure_;
};
}  // namespace screen_loop
}  // namespace dvs_screen_sim
