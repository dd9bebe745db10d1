#pragma once
// IMU fusion for the line tracker (issue 17), the StatePropagator that carries the tracker's pose
// from event to event with an IMU (ROS-free):
//  - before each event's vision update, the filter (ImuEkf) is advanced through the IMU samples
//    to the event's time and the tracker's pose moves with it (per event: the filter's mean only);
//  - every `update_period`, where the buffered events put the camera (one undamped Gauss-Newton
//    step from the tracker's pose on their normal equations; in a partial view the tracker's
//    pose) is the filter's measurement, with the vision's own covariance (scaled); the tracker
//    then continues from the filter's estimate;
//  - through an event-free gap the IMU alone carries the pose (LineTracker re-seeds its buffers at
//    the predicted pose, no loss) for at most `max_bridge`;
//  - after every (re)start the filter first runs beside the vision without moving its pose, and
//    is used only once its predictions have agreed with the vision for 50 updates (and again
//    whenever they stop agreeing); disagreeing for 2 s, or biases beyond 4x their prior sigma,
//    set it aside for 2 s;
//  - an estimated gravity (started from the specific force of the last 0.2 s, tilted when the
//    camera was accelerating) is checked first: for `gravity_check` a second filter with the
//    accelerometer runs beside the tracker's, which meanwhile uses the gyroscope and a
//    constant-velocity position (as accurate on the flips; only a blackout needs the
//    accelerometer). Plausible biases confirm the gravity and the tracker's filter continues as
//    the second one; an accelerometer bias beyond 4x its prior rejects it: gyroscope only
//    (GYRO_ONLY) until the next start. At range the vision cannot tell a tilted gravity from its
//    own slowly varying error, so an unchecked wrong gravity would make tracking worse.
// Health: the IMU is used only while its stream is fresh (newest sample within `max_latency` of
// the event), plausible (finite, within the rate / force limits, no stuck axis, an accelerometer
// in m/s^2) and in agreement with the vision (the filter's innovations); otherwise the tracker
// runs on vision alone, as without an IMU, and status() says why.
#include <dvs_driver/imu_sample.h>
#include <dvs_line_tracker/imu_ekf.h>
#include <dvs_line_tracker/imu_fusion_params.h>
#include <dvs_line_tracker/state_propagator.h>

#include <cstdint>
#include <string>
#include <vector>

namespace dvs_line_tracker
{
enum class ImuStatus
{
  kWaiting,    ///< no sample yet, or tracking has not started
  kChecking,   ///< filtered beside the vision, not used until its predictions agree with it
  kOk,         ///< fused
  kGyroOnly,   ///< fused without the accelerometer: an estimated gravity being checked, or rejected (gravityRejected())
  kLate,       ///< the newest sample is older than max_latency at the events (missing or late stream)
  kAbsurd,     ///< implausible samples (limits, stuck axis, units)
  kDisagrees,  ///< the filter kept disagreeing with the vision: vision alone for a while
};
const char* toString(ImuStatus status);
/// The filter moves the tracker's pose (with the accelerometer, or without it: GYRO_ONLY).
inline bool isFused(ImuStatus s) { return s == ImuStatus::kOk || s == ImuStatus::kGyroOnly; }
/// The filter runs (fused, or checked before it is fused): event packets wait for its samples.
inline bool isEngaged(ImuStatus s) { return isFused(s) || s == ImuStatus::kChecking; }
/// An IMU stream is there but set aside (late, absurd, disagreeing): the operator must be told.
inline bool isSetAside(ImuStatus s) { return !isEngaged(s) && s != ImuStatus::kWaiting; }

struct ImuFusionStats
{
  uint64_t samples = 0;            ///< accepted samples
  uint64_t samples_out_of_order = 0;
  uint64_t samples_absurd = 0;
  uint64_t updates = 0;            ///< vision updates of the filter
  uint64_t updates_rejected = 0;   ///< innovation outside the gate
  double nis_sum = 0;              ///< sum of the accepted updates' normalised innovations squared (6 dof)
  uint64_t fallbacks = 0;          ///< times the IMU went from fused to not fused
  uint64_t gaps_bridged = 0;       ///< event-free gaps carried by the IMU (counted by LineTracker)
};

/// The filter's estimate predicted to a time, for odometry outputs.
struct ImuOdometry
{
  int64_t t_ns = 0;
  Pose T_world_camera;
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();         ///< camera centre, world frame, m/s
  Eigen::Vector3d angular_velocity_camera = Eigen::Vector3d::Zero();///< camera axes, rad/s
  Matrix6d pose_covariance = Matrix6d::Zero();  ///< (rotation error, camera axes; position, world)
  Eigen::Matrix3d velocity_covariance = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d angular_velocity_covariance = Eigen::Matrix3d::Zero();
};

class ImuPropagator : public StatePropagator
{
public:
  /// Throws std::invalid_argument naming the parameter when the vectors do not parse.
  explicit ImuPropagator(const ImuFusionParams& params);
  ImuPropagator(const ImuPropagator&) = delete;  // the filter refers to the parameters held here
  ImuPropagator& operator=(const ImuPropagator&) = delete;

  /// A sample in the IMU's clock (time_offset is added here). Older than the newest: dropped and
  /// counted. Implausible: dropped, counted, and the stream is marked absurd for a while.
  void addSample(const dvs_driver::ImuSample& sample);
  /// A sample's time in the events' clock (its stamp + imu_time_offset).
  int64_t eventTimeOf(const dvs_driver::ImuSample& sample) const { return sample.t_ns + time_offset_ns_; }

  void propagate(EstimatorState& state, int64_t t_ns) override;
  void restart(const EstimatorState& state, int64_t t_ns) override;
  bool active(int64_t t_ns) const override;
  void noteGapBridged() override { ++stats_.gaps_bridged; }
  int64_t maxBridgeNs() const override { return max_bridge_ns_; }

  /// The filter's estimate predicted to t_ns (>= the last event's time); false while not fused.
  bool odometry(int64_t t_ns, ImuOdometry& out) const;
  ImuStatus status() const { return status_; }
  /// The estimated gravity was rejected: gyroscope only until the next start (a fault to report).
  bool gravityRejected() const { return gyro_only_; }
  /// Why the IMU is not (fully) fused ("" when it is).
  const std::string& statusMessage() const { return message_; }
  const ImuFusionStats& stats() const { return stats_; }
  const ImuEkf& filter() const { return ekf_; }
  /// Time (events' clock) of the newest sample, INT64_MIN before the first.
  int64_t newestSampleNs() const { return newest_ns_; }

private:
  struct Sample
  {
    int64_t t_ns;
    Eigen::Vector3d gyro, accel;
  };
  /// Where the filter's mean is in time, the sample in force there, and the time not yet
  /// propagated into the covariance (done once per sample period).
  struct Cursor
  {
    Sample sample{};
    int64_t t_ns = 0;
    double pending_cov_dt = 0;
    void meanTo(ImuEkf& f, int64_t t_to);
    void next(ImuEkf& f, const Sample& s);
    void flushCovariance(ImuEkf& f);
  };
  void setStatus(ImuStatus s, const std::string& message);
  /// Vision alone from `t_ns` for kDistrustNs, then a fresh start; `forget`: without what was learned.
  void setAside(ImuStatus s, const std::string& message, int64_t t_ns, bool forget = false);
  /// The samples up to t_ns consumed (the filter's mean and covariance carried to each) and the
  /// filter's time set to t_ns; `moved` (the tracker's state, when the IMU is trusted) carried
  /// along with the filter's nominal motion, sample by sample. The mean itself is carried
  /// between samples only when it is needed (catchUp): per event one increment, no propagation.
  void advanceTo(int64_t t_ns, EstimatorState* moved);
  /// `state`'s pose moved with the nominal motion of the sample in force from due_ns_ to t_ns.
  void moveWithFilter(EstimatorState& state, int64_t t_ns);
  /// The filter's mean (and the gravity check's) carried to due_ns_.
  void catchUp();
  void updateWithVision(EstimatorState& state);
  bool gravityEstimated() const { return !extrinsics_.gravity_world; }
  void setFusedStatus();
  /// While an estimated gravity is checked: the checking filter's vision update, then confirmed
  /// (ekf_ continues with the accelerometer) or rejected (gyroscope only until the next start).
  void checkGravity(const Pose& measured);
  /// The vision's measurement for the filter: where the buffered events put the camera (the
  /// tracker's pose in a partial view).
  static Pose visionMeasurement(const EstimatorState& state);
  /// The estimated gravity is wrong: gyroscope only until the next start, said why.
  void rejectGravity(double accel_bias);
  bool plausible(const Sample& s);

  ImuFusionParams params_;
  ImuExtrinsics extrinsics_;
  ImuEkf ekf_;
  std::vector<Sample> ring_;  ///< samples not yet consumed, ring buffer
  size_t head_ = 0, count_ = 0;
  Cursor cursor_;
  bool have_current_ = false;
  int64_t t_last_update_ = 0, newest_ns_ = INT64_MIN, previous_event_ns_ = 0;
  int64_t due_ns_ = 0;  ///< the filter's time (the tracker's pose is there); its mean is at cursor_.t_ns <= due_ns_
  double sample_period_s_ = 1e-3;  ///< the latest interval between samples
  Matrix6d vision_covariance_ = Matrix6d::Zero();  ///< the latest Gauss-Newton covariance (unscaled)
  int64_t max_latency_ns_, max_bridge_ns_, update_period_ns_, time_offset_ns_, gravity_check_ns_;
  ImuStatus status_ = ImuStatus::kWaiting;
  std::string message_ = "no IMU sample yet";
  int64_t distrust_until_ns_ = INT64_MIN;  ///< absurd / disagreeing: not fused before this
  bool trusted_ = false;       ///< agrees with the vision: moves the tracker's pose
  bool forget_learned_ = false;  ///< the next start forgets biases and gravity (they went implausible)
  bool gyro_only_ = false;     ///< the accelerometer does not move the tracker (until the next start)
  bool checking_gravity_ = false;  ///< an estimated gravity being checked (gravity_check_): ekf_ without the accelerometer
  bool gravity_checked_ = false;   ///< the estimated gravity was confirmed (kept across restarts)
  ImuEkf gravity_check_;           ///< with the accelerometer, beside ekf_ while checking the gravity
  Cursor gravity_cursor_;
  int64_t started_ns_ = 0;
  std::string gyro_only_reason_;
  double nis_mean_ = 0;        ///< running mean of the scaled normalised innovations squared
  uint64_t updates_since_restart_ = 0;
  int64_t checking_since_ns_ = 0;
  // Plausibility over the recent samples.
  Eigen::Vector3d last_gyro_ = Eigen::Vector3d::Zero(), last_accel_ = Eigen::Vector3d::Zero();
  int same_count_[6] = {0, 0, 0, 0, 0, 0};
  double accel_norm_sum_ = 0;
  int accel_norm_n_ = 0;
  ImuFusionStats stats_;
  bool tracking_ = false;
};
}  // namespace dvs_line_tracker
