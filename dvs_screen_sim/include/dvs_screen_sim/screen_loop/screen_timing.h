#pragma once
// Screen timing for the screen in the loop (thesis ch. 3.4.2): the refresh period (measured as
// the time between two subsequent buffer swaps with vsync), the apparent motion per refresh
// (the screen blurs motion faster than one screen pixel per refresh), and a time-scale factor
// that slows the playback down and maps time stamps back to the trajectory's time.
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/screen_loop/gl_screen_renderer.h>
#include <dvs_screen_sim/screen_loop/projection_pipeline.h>
#include <dvs_screen_sim/trajectory.h>

#include <string>
#include <vector>

namespace dvs_screen_sim
{
namespace screen_loop
{
/// Refresh period from swap completion times [s]: the median interval (robust to a missed
/// frame or a scheduling hiccup). 0 until two swaps were seen.
class RefreshPeriodEstimator
{
public:
  void addSwapTime(double t);
  double period() const;
  size_t intervals() const { return intervals_.size(); }

private:
  double last_ = 0;
  bool has_last_ = false;
  std::vector<double> intervals_;
};

/// The DVS's time base seen from the host clock: offset = DVS time - host time, estimated from
/// event packets as the largest (last event stamp - arrival time): a packet arrives after its
/// last event by the transfer latency (>= 0), so the largest difference is the least delayed.
/// Ground truth of what the screen shows at host time h is then stamped h + offset.
class DvsClockOffset
{
public:
  void addPacket(int64_t last_event_ns, int64_t arrival_host_ns);
  bool valid() const { return packets_ > 0; }
  int64_t offsetNs() const { return offset_ns_; }
  int64_t toDvsNs(int64_t host_ns) const { return host_ns + offset_ns_; }
  size_t packets() const { return packets_; }

private:
  int64_t offset_ns_ = 0;
  size_t packets_ = 0;
};

/// Playback slowed down by `factor` (>= 1 shows the trajectory `factor` times slower; the
/// thesis used 5x to avoid the screen's motion blur). Time stamps of the recording are mapped
/// back to trajectory time, so ground truth and the DVS's (rescaled) events share the
/// trajectory's time base.
struct TimeScale
{
  double factor = 1.0;
  /// Throws std::invalid_argument unless factor > 0 and finite.
  void validate() const;
  double trajectoryTime(double playback_elapsed) const { return playback_elapsed / factor; }
  double playbackTime(double trajectory_t) const { return trajectory_t * factor; }
  /// An event time stamp recorded `playback` ns after the playback start -> trajectory ns.
  int64_t rescaleStampNs(int64_t playback_ns_since_start) const
  {
    return static_cast<int64_t>(std::llround(static_cast<double>(playback_ns_since_start) / factor));
  }
};

/// Largest displacement [window pixels] of the scene's points (polygon vertices and points
/// every `spacing` m along the lines) through the corrected pipeline between trajectory times t
/// and t + dt. Points behind the virtual camera are skipped.
double screenMotionPx(const ProjectionPipeline& pipeline, const Trajectory& trajectory, const std::vector<Eigen::Vector3d>& points,
                      double t, double dt, int window_width, int window_height);

/// Sample points of a scene (polygon vertices + points every `spacing` m along their edges) and
/// of world lines, for screenMotionPx.
std::vector<Eigen::Vector3d> motionSamplePoints(const Scene& scene, const std::vector<WorldLine>& lines,
                                                double spacing = 0.05);

struct MotionCheck
{
  double max_px_per_refresh = 0;  ///< worst apparent motion over the trajectory
  double worst_time = 0;          ///< trajectory time where it happens
  /// The smallest time-scale factor keeping the motion <= 1 screen px per refresh.
  double suggested_time_scale = 1.0;
};
/// Scans [t0, t1] in steps of one refresh of playback (refresh_period / time_scale of
/// trajectory time).
MotionCheck checkApparentMotion(const ProjectionPipeline& pipeline, const Trajectory& trajectory,
                                const std::vector<Eigen::Vector3d>& points, double t0, double t1, double refresh_period,
                                const TimeScale& time_scale, int window_width, int window_height);
/// Empty when fine, else the warning text (thesis 3.4.2).
std::string motionWarning(const MotionCheck& check);
}  // namespace screen_loop
}  // namespace dvs_screen_sim
