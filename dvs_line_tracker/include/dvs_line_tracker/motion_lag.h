#pragma once
// How far the vision estimate may trail a moving camera, as a covariance. The pose fits the
// segment buffers' events (buffer_size per visible map segment), which the edges drew over the
// last `span` = buffer_size x visible segments / attributed events per second; on average they
// are span / 2 old, and a camera turning at w and moving at v is by then w span / 2 and
// v span / 2 further. The Gauss-Newton covariance (visionPoseCovariance) holds only the events'
// scatter about their lines, which that lag does not show: over the 192-scene sweep it put 62 %
// of the position errors inside 1 sigma and 95 % inside 3, 43 scenes (fast flips, far squares)
// under 90 % inside 3 sigma; with the lag term 72 % and 97 %, 22 scenes. Checked against the
// truth, the estimate trails by 0.495 x speed x span (BENCHMARKS.md, thirty-sixth session).
//
// The motion is the estimate's own: its pose sampled every millisecond of event time while
// tracking, differenced over the last 5 ms (no IMU needed). Each axis gets the variance of the
// whole rate (|w| span / 2 on every rotation axis, |v| span / 2 on every position axis): a turn
// about one axis also moves the estimate along the lateral axes it is coupled with.
//
// With an IMU, the filter is corrected by those same lagging vision poses: `~odometry` adds the
// term to the filter's covariance too (its rotation errors inside 3 sigma on the flips: 90.7 /
// 95.8 % -> 98.6 / 100 % at 1.4 / 2.3 m).
#include <dvs_line_tracker/pose_types.h>

#include <array>
#include <cstdint>
#include <limits>

namespace dvs_line_tracker
{
class MotionLag
{
public:
  static constexpr int64_t kSamplePeriodNs = 1000000;  ///< one pose per millisecond of event time
  static constexpr int64_t kRateWindowNs = 5000000;    ///< the rate over the last 5 ms (or more)
  /// Samples further apart than this say nothing about the current motion.
  static constexpr int64_t kMaxRateWindowNs = 500000000;

  /// Forget the motion (a new track).
  void reset()
  {
    count_ = 0;
    next_ns_ = std::numeric_limits<int64_t>::min();
  }
  /// While tracking, after every event: keeps the pose at most every kSamplePeriodNs, with the
  /// count of attributed events so far (the event rate the buffers fill at).
  void sample(int64_t t_ns, const Pose& pose, uint64_t events_attributed)
  {
    if (t_ns >= next_ns_)
      record(t_ns, pose, events_attributed);
  }
  /// The variance to add to the vision pose covariance (rotation error in camera axes, then
  /// position in the world, as visionPoseCovariance): diagonal; zero while the motion is not
  /// known (less than kRateWindowNs of samples, or no event attributed over it).
  Matrix6d covariance(int visible_segments, int buffer_size) const;

  /// The estimate's angular (rad/s) and linear (m/s) speed and the buffers' span (s) behind the
  /// covariance; false when the motion is not known.
  bool motion(int visible_segments, int buffer_size, double& angular_speed, double& linear_speed,
              double& span_s) const;
  /// Attributed events per second over the same window; negative when not known.
  double attributedRate() const;

private:
  void record(int64_t t_ns, const Pose& pose, uint64_t events_attributed);

  struct Sample
  {
    int64_t t_ns = 0;
    Pose pose;
    uint64_t events_attributed = 0;
  };
  /// The latest sample and the newest one at least kRateWindowNs older (at most
  /// kMaxRateWindowNs apart, with events attributed in between); false when there is none.
  bool window(const Sample*& then, const Sample*& now) const;
  /// Attributed events per second from `then` to `now`.
  static double eventsPerSecond(const Sample& then, const Sample& now);
  static constexpr int kCapacity = 8;  ///< > kRateWindowNs / kSamplePeriodNs samples
  std::array<Sample, kCapacity> ring_;
  int head_ = 0;  ///< next write
  int count_ = 0;
  int64_t next_ns_ = std::numeric_limits<int64_t>::min();
};
}  // namespace dvs_line_tracker
