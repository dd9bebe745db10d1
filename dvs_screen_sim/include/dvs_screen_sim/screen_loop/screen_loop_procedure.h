#pragma once
// The screen-in-the-loop procedure (thesis ch. 3), written once: align (blink the circle grid,
// detect it in the DVS's events, set the correction H), check (the apparent motion per refresh;
// the blinking line grid), play (the scene along a trajectory, slowed by a time scale, with the
// ground truth of every displayed frame) and rescale (the events' and the ground truth's time
// stamps back to trajectory time). ROS-free. What it runs on is injected:
//   - a LoopScreen: the OpenGL window and when its frames are shown (a real window refreshing in
//     wall-clock time, window_screen.h, or the virtual monitor filmed by the software DVS,
//     emulated_screen_loop.h);
//   - a LoopEventSource: the DVS's events and its clock (a live sensor's packets,
//     live_event_collector.h, or the software DVS).
// The screen_loop node (ScreenLoopRos), the emulation (EmulatedScreenLoop, emulate_screen_loop)
// and the tests all run this class.
#include <dvs_calibration/camera_model.h>
#include <dvs_calibration/pose.h>
#include <dvs_driver/event.h>
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/screen_loop/gl_screen_renderer.h>
#include <dvs_screen_sim/screen_loop/grid_alignment.h>
#include <dvs_screen_sim/screen_loop/line_grid_check.h>
#include <dvs_screen_sim/screen_loop/projection_pipeline.h>
#include <dvs_screen_sim/screen_loop/screen_timing.h>
#include <dvs_screen_sim/trajectory.h>

#include <functional>
#include <limits>
#include <string>

namespace dvs_screen_sim
{
namespace screen_loop
{
/// One frame the screen is about to show.
struct Frame
{
  int64_t index = 0;     ///< the screen's refresh counter (blink phases follow it)
  int64_t k = 0;         ///< frames since the first frame of this showFrames() call
  int64_t start_ns = 0;  ///< screen clock [ns] when the frame is drawn (emulated: when it is shown)
  double t = 0;          ///< [s] of screen time since the first frame of this call started
};

/// Draws a frame into the renderer's back buffer.
using DrawFrame = std::function<void(const Frame& frame, ScreenCanvas& gl)>;
/// Told when a frame is on the screen: `shown_ns` (screen clock) is the start of its display.
using FrameShown = std::function<void(const Frame& frame, int64_t shown_ns)>;

/// The screen the procedure draws on.
class LoopScreen
{
public:
  virtual ~LoopScreen() = default;
  virtual ScreenCanvas& canvas() = 0;
  /// [s] between two refreshes (measured on a real screen, configured on an emulated one).
  virtual double refreshPeriod() const = 0;
  /// Show frames from the next refresh on for `duration` seconds of screen time: every frame
  /// whose start lies within [0, duration] after the first one's is drawn by `draw`, then
  /// shown, then reported to `shown` (may be empty). Returns false when interrupted (window
  /// closed, shutting down).
  virtual bool showFrames(double duration, const DrawFrame& draw, const FrameShown& shown) = 0;
};

/// The DVS filming the screen: its events and its clock.
class LoopEventSource
{
public:
  virtual ~LoopEventSource() = default;
  /// The DVS time stamp [ns] of a screen-clock time [ns].
  virtual int64_t dvsTimeNs(int64_t screen_ns) const = 0;
  /// Whether dvsTimeNs is known (a live sensor: once its first packet arrived).
  virtual bool clockValid() const = 0;
  /// Keep the events delivered from now on, until takeKept(). `from_dvs_ns` is now in the DVS's
  /// clock: a source that knows where "now" is in its stream (the software DVS) keeps exactly
  /// the events stamped from then on; a live sensor keeps what arrives from now on (its packets
  /// come late by the transfer latency, and a lagging sensor must not lose the window).
  virtual void keepFrom(int64_t from_dvs_ns) = 0;
  /// Deliver the events still in flight (the end of a recording).
  virtual void drain() = 0;
  /// Stop keeping; the kept events in time order.
  virtual dvs_driver::EventVector takeKept() = 0;
};

struct ProcedureConfig
{
  AlignmentPattern pattern;
  GridAlignmentConfig detector;
  double alignment_settle = 0.1;    ///< [s] of blinking before the events count (the screen switching on)
  double alignment_duration = 0.5;  ///< [s] of events per alignment attempt
  int alignment_attempts = 5;
  /// Attempts whose residual RMS [DVS px] is above this are refused (and retried).
  double max_alignment_residual = std::numeric_limits<double>::infinity();
  /// [s] the monitor's pixel response time: the DVS sees a frame once its light is half-way,
  /// half of it after the frame switch; the ground truth is stamped then.
  double response_time = 0.0;
  /// Refreshes showing the trajectory's start pose before the playback (a settled screen).
  int settle_frames = 0;
  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

enum class LogLevel
{
  Info,
  Warn,
  Error
};
using ProcedureLog = std::function<void(LogLevel level, const std::string& message)>;

/// What play() returns, in the trajectory's time base (0 = the playback's first frame).
struct Playback
{
  dvs_driver::EventVector events;     ///< time stamps rescaled: (stamp - start_dvs_ns) / time scale
  dvs_calibration::Trajectory shown;  ///< one pose per displayed frame, stamped when the DVS sees it
  int64_t start_dvs_ns = 0;           ///< the DVS time of the playback's start (add it for absolute stamps)
  bool completed = false;             ///< false when the screen was interrupted
};

class ScreenLoopProcedure
{
public:
  /// `camera`: the DVS's intrinsics (the pipeline's and the detector's). `log` may be empty.
  ScreenLoopProcedure(const ProcedureConfig& config, const dvs_calibration::CameraModel& camera, LoopScreen& screen,
                      LoopEventSource& events, ProcedureLog log = {});

  /// Align: blink the circle grid (alignment_settle + alignment_duration per attempt), detect it
  /// in the events, compute H; up to alignment_attempts attempts, refusing residuals above
  /// max_alignment_residual. On success the pipeline's correction is set. Returns the last
  /// attempt (ok false with the reason when none succeeded).
  GridAlignment align();

  /// Check: blink world `lines` (drawn `width` m wide at the virtual pose, through the corrected
  /// or uncorrected pipeline) for `frames` refreshes; returns the events after the first one.
  dvs_driver::EventVector showLines(const Pose& T_world_virtual, const std::vector<WorldLine>& lines, double width,
                                    bool corrected, int frames);

  /// Check: the apparent motion per refresh of `scene` along `trajectory` over [0, duration] at
  /// `time_scale` (thesis 3.4.2).
  MotionCheck checkMotion(const Scene& scene, const Trajectory& trajectory, double duration,
                          const TimeScale& time_scale) const;

  /// Play `scene` along `trajectory` from trajectory time 0 to `duration`, slowed by
  /// `time_scale`: each frame shows the pose at the centre of its display interval; the ground
  /// truth of a frame is stamped half a refresh plus half the response time after it is shown.
  /// `live` (may be empty) receives each displayed pose at once, stamped in the DVS's time base.
  /// Rescale: the events after the playback's start and the shown poses come back in trajectory
  /// time (Playback). `keep_events` false: no events are kept (nothing to record).
  Playback play(const Scene& scene, const Trajectory& trajectory, double duration, const TimeScale& time_scale,
                const std::function<void(const StampedPose&)>& live = {}, bool keep_events = true);

  ProjectionPipeline& pipeline() { return pipeline_; }
  const ProjectionPipeline& pipeline() const { return pipeline_; }
  const ProcedureConfig& config() const { return config_; }

private:
  void log(LogLevel level, const std::string& message) const;
  double period() const;

  ProcedureConfig config_;
  dvs_calibration::CameraModel camera_;
  LoopScreen& screen_;
  LoopEventSource& events_;
  ProcedureLog log_;
  ProjectionPipeline pipeline_;
};
}  // namespace screen_loop
}  // namespace dvs_screen_sim
