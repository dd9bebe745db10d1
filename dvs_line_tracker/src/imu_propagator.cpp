#include <dvs_line_tracker/imu_propagator.h>
#include <dvs_line_tracker/pose_estimator.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace dvs_line_tracker
{
namespace
{
constexpr size_t kRingCapacity = 4096;       // > 4 s of samples at 1 kHz
constexpr int kStuckSamples = 200;            // an axis repeating its exact value this often is stuck
constexpr int kUnitsWindow = 500;             // samples over which |accel| is averaged
constexpr double kMinMeanAccel = 3.0;         // m/s^2: below, the accelerometer is not in m/s^2 (g?)
constexpr double kMaxMeanAccel = 40.0;
constexpr double kNisAlpha = 1.0 / 50;        // running mean of the innovations over ~50 updates
constexpr double kAgreeNis = 600.0;           // scaled mean innovation below which the IMU agrees (sound: ~50)
constexpr uint64_t kTrustUpdates = 50;        // updates of agreement before the IMU is used
constexpr int64_t kMaxCheckingNs = 2000000000; // disagreeing this long: vision alone for kDistrustNs
constexpr double kBiasSigmas = 4.0;           // |bias| beyond this x its prior sigma (norm of 3 axes): implausible
constexpr int64_t kGravityWindowNs = 200000000; // accelerometer samples averaged for the first gravity
constexpr double kCheckedBiasSigmas = 2.0;    // an estimated gravity is confirmed with the accel bias inside this x its prior
const char* const kCheckingGravity = "checking the estimated gravity: gyroscope only until then";
constexpr double kGate = 200.0;               // chi2 (6 dof) of an update's innovation, at most
constexpr int64_t kDistrustNs = 2000000000;   // vision alone this long after an absurd stream / disagreement
constexpr double kOptimumDamping = 1e-6;      // the vision's measurement: Gauss-Newton, damped only against a singular information

const ImuExtrinsics& parsed(const ImuFusionParams& p, ImuExtrinsics& out)
{
  const std::string err = parseImuExtrinsics(p, out);
  if (!err.empty())
    throw std::invalid_argument("dvs_line_tracker: " + err);
  return out;
}
}  // namespace

const char* toString(ImuStatus status)
{
  switch (status)
  {
    case ImuStatus::kWaiting:
      return "WAITING";
    case ImuStatus::kChecking:
      return "CHECKING";
    case ImuStatus::kOk:
      return "OK";
    case ImuStatus::kGyroOnly:
      return "GYRO_ONLY";
    case ImuStatus::kLate:
      return "LATE";
    case ImuStatus::kAbsurd:
      return "ABSURD";
    case ImuStatus::kDisagrees:
      return "DISAGREES";
  }
  return "?";
}

ImuPropagator::ImuPropagator(const ImuFusionParams& params)
  : params_(params)
  , extrinsics_()
  , ekf_(params_, parsed(params_, extrinsics_))
  , ring_(kRingCapacity)
  , max_latency_ns_(static_cast<int64_t>(params.max_latency_s * 1e9))
  , max_bridge_ns_(static_cast<int64_t>(params.max_bridge_s * 1e9))
  , update_period_ns_(static_cast<int64_t>(params.update_period_s * 1e9))
  , time_offset_ns_(static_cast<int64_t>(params.time_offset_s * 1e9))
  , gravity_check_ns_(static_cast<int64_t>(params.gravity_check_s * 1e9))
  , gravity_check_(params_, extrinsics_)
{
}

void ImuPropagator::setStatus(ImuStatus s, const std::string& message)
{
  if (status_ == ImuStatus::kOk && s != ImuStatus::kOk)
    ++stats_.fallbacks;
  status_ = s;
  message_ = message;
}

void ImuPropagator::setAside(ImuStatus s, const std::string& message, int64_t t_ns, bool forget)
{
  tracking_ = false;
  trusted_ = false;
  forget_learned_ = forget_learned_ || forget;
  distrust_until_ns_ = t_ns + kDistrustNs;
  setStatus(s, message);
}

bool ImuPropagator::plausible(const Sample& s)
{
  if (!s.gyro.allFinite() || !s.accel.allFinite())
  {
    message_ = "an IMU sample is not finite";
    return false;
  }
  if (s.gyro.cwiseAbs().maxCoeff() > params_.max_gyro_rad_s)
  {
    message_ = "angular rate " + std::to_string(s.gyro.cwiseAbs().maxCoeff()) + " rad/s exceeds imu_max_gyro (deg/s given as rad/s?)";
    return false;
  }
  if (s.accel.cwiseAbs().maxCoeff() > params_.max_accel_m_s2)
  {
    message_ = "specific force " + std::to_string(s.accel.cwiseAbs().maxCoeff()) + " m/s^2 exceeds imu_max_accel";
    return false;
  }
  // A stuck axis repeats its exact value; noise never does.
  bool stuck = false;
  for (int a = 0; a < 3; ++a)
  {
    same_count_[a] = s.gyro[a] == last_gyro_[a] ? same_count_[a] + 1 : 0;
    same_count_[3 + a] = s.accel[a] == last_accel_[a] ? same_count_[3 + a] + 1 : 0;
    stuck |= same_count_[a] >= kStuckSamples || same_count_[3 + a] >= kStuckSamples;
  }
  last_gyro_ = s.gyro;
  last_accel_ = s.accel;
  if (stuck)
  {
    message_ = "an IMU axis has repeated the same value for " + std::to_string(kStuckSamples) + " samples (stuck)";
    return false;
  }
  accel_norm_sum_ += s.accel.norm();
  if (++accel_norm_n_ == kUnitsWindow)
  {
    const double mean = accel_norm_sum_ / accel_norm_n_;
    accel_norm_sum_ = 0;
    accel_norm_n_ = 0;
    if (mean < kMinMeanAccel || mean > kMaxMeanAccel)
    {
      message_ = "the accelerometer's mean magnitude is " + std::to_string(mean) +
                 " (expected about 9.81 m/s^2: wrong units?)";
      return false;
    }
  }
  return true;
}

void ImuPropagator::addSample(const dvs_driver::ImuSample& in)
{
  Sample s;
  s.t_ns = eventTimeOf(in);
  s.gyro = Eigen::Vector3d(in.gyro[0], in.gyro[1], in.gyro[2]);
  s.accel = Eigen::Vector3d(in.accel[0], in.accel[1], in.accel[2]);
  if (newest_ns_ != INT64_MIN && s.t_ns <= newest_ns_)
  {
    ++stats_.samples_out_of_order;
    return;
  }
  if (!plausible(s))
  {
    ++stats_.samples_absurd;
    const std::string why = message_;
    setAside(ImuStatus::kAbsurd, why, s.t_ns);
    return;
  }
  if (newest_ns_ != INT64_MIN)
    sample_period_s_ = (s.t_ns - newest_ns_) * 1e-9;
  newest_ns_ = s.t_ns;
  ++stats_.samples;
  if (count_ == ring_.size())
  {
    head_ = (head_ + 1) % ring_.size();  // oldest dropped (not tracking: nothing consumes)
    --count_;
  }
  ring_[(head_ + count_) % ring_.size()] = s;
  ++count_;
}

bool ImuPropagator::active(int64_t t_ns) const
{
  return tracking_ && trusted_ && isFused(status_) && newest_ns_ != INT64_MIN && t_ns - newest_ns_ <= max_latency_ns_;
}

void ImuPropagator::restart(const EstimatorState& state, int64_t t_ns)
{
  tracking_ = false;
  // The sample in force at t_ns: the newest not after it.
  Eigen::Vector3d accel_sum = Eigen::Vector3d::Zero();
  int accel_n = 0;
  while (count_ > 0 && ring_[head_].t_ns <= t_ns)
  {
    if (ring_[head_].t_ns >= t_ns - kGravityWindowNs)
    {
      accel_sum += ring_[head_].accel;
      ++accel_n;
    }
    cursor_.sample = ring_[head_];
    have_current_ = true;
    head_ = (head_ + 1) % ring_.size();
    --count_;
  }
  if (!have_current_ || t_ns - cursor_.sample.t_ns > max_latency_ns_)
  {
    setStatus(newest_ns_ == INT64_MIN ? ImuStatus::kWaiting : ImuStatus::kLate,
              newest_ns_ == INT64_MIN ? "no IMU sample yet" : "no IMU sample within imu_max_latency of the events");
    return;
  }
  if (t_ns < distrust_until_ns_)
    return;  // status (absurd / disagrees) stays
  // An unknown gravity starts against the mean specific force of the last samples.
  // What was learned is kept, except after implausible biases, and an estimated gravity that
  // was not confirmed.
  const ImuEkf::Keep keep = forget_learned_                          ? ImuEkf::Keep::kNothing
                            : gravityEstimated() && !gravity_checked_ ? ImuEkf::Keep::kGyroBias
                                                                      : ImuEkf::Keep::kAll;
  ekf_.start(state.pose, accel_n > 0 ? Eigen::Vector3d(accel_sum / accel_n) : cursor_.sample.accel, keep);
  if (forget_learned_)
    gravity_checked_ = false;
  forget_learned_ = false;
  gyro_only_ = false;
  cursor_.t_ns = due_ns_ = t_last_update_ = checking_since_ns_ = previous_event_ns_ = started_ns_ = t_ns;
  cursor_.pending_cov_dt = 0;
  // An estimated gravity that was not confirmed yet: the tracker's filter runs without the
  // accelerometer (gyroscope, constant-velocity position) while a second filter with it checks
  // the gravity.
  checking_gravity_ = gravityEstimated() && !gravity_checked_;
  ekf_.useAccelerometer(!checking_gravity_);
  if (checking_gravity_)
  {
    gravity_check_ = ekf_;
    gravity_check_.useAccelerometer(true);
    gravity_cursor_ = cursor_;
  }
  trusted_ = false;
  nis_mean_ = 0;
  updates_since_restart_ = 0;
  tracking_ = true;
  setStatus(ImuStatus::kChecking, "checking the IMU against the vision before it is used");
}

void ImuPropagator::Cursor::meanTo(ImuEkf& f, int64_t t_to)
{
  if (t_to <= t_ns)
    return;
  // The sample is held until the next one (zero-order hold; a first-order extrapolation along
  // the last two samples' slope was measured no better: the flips' angular acceleration moves
  // a 150 ms integration by 0.005 deg either way, and the slope doubles the noise).
  const double dt = (t_to - t_ns) * 1e-9;
  f.propagateMean(sample.gyro, sample.accel, dt);
  pending_cov_dt += dt;
  t_ns = t_to;
}

void ImuPropagator::Cursor::next(ImuEkf& f, const Sample& s)
{
  meanTo(f, s.t_ns);
  flushCovariance(f);
  sample = s;
}

void ImuPropagator::Cursor::flushCovariance(ImuEkf& f)
{
  f.propagateCovariance(sample.gyro, sample.accel, pending_cov_dt);
  pending_cov_dt = 0;
}

void ImuPropagator::advanceTo(int64_t t_ns, EstimatorState* moved)
{
  while (count_ > 0 && ring_[head_].t_ns <= t_ns)
  {
    const Sample& s = ring_[head_];
    if (moved)
      moveWithFilter(*moved, s.t_ns);
    if (s.t_ns < due_ns_)
      catchUp();  // a late sample: the held one is in force until the filter's time
    cursor_.next(ekf_, s);
    if (checking_gravity_)
      gravity_cursor_.next(gravity_check_, s);
    head_ = (head_ + 1) % ring_.size();
    --count_;
  }
  if (moved)
    moveWithFilter(*moved, t_ns);
  due_ns_ = std::max(due_ns_, t_ns);
}

void ImuPropagator::moveWithFilter(EstimatorState& state, int64_t t_ns)
{
  if (t_ns <= due_ns_)
    return;
  const Vector6d d = ekf_.cameraIncrement(cursor_.sample.gyro, cursor_.sample.accel, (due_ns_ - cursor_.t_ns) * 1e-9,
                                          (t_ns - cursor_.t_ns) * 1e-9, state.pose.R_camera_world);
  state.pose.applyCameraIncrement(d);
  state.x_accumulated += d;
  due_ns_ = t_ns;
}

void ImuPropagator::catchUp()
{
  cursor_.meanTo(ekf_, due_ns_);
  if (checking_gravity_)
    gravity_cursor_.meanTo(gravity_check_, due_ns_);
}

Pose ImuPropagator::visionMeasurement(const EstimatorState& state)
{
  // The tracker's pose is the filter's previous estimate plus one update period of damped
  // per-event steps: in a weakly observable direction (the lateral translation / rotation pair
  // of a far target) only a small part of what the buffered events say. Taken as the
  // measurement, the filter moved by its gain times that part, and a first pose's error there
  // stayed for seconds (a slow camera 2-4 m from a square: 2-3x the error of vision alone, 0-25 %
  // of the time tracked; BENCHMARKS.md, fortieth session). So the measurement is where the
  // buffered events put the camera: one undamped Gauss-Newton step on their normal equations,
  // whose covariance is the one the filter is given. Except in a partial view: there the events
  // do not constrain that pair (part of the map is out of view), the undamped step follows the
  // model's errors at the image border, and the tracker's stronger damping is what holds the
  // pair steady (the 1.4 m flips, whose partial phases it was made for, lost 10 % of their
  // accuracy and twice the error after a blackout with the undamped step there).
  Pose measured = state.pose;
  Vector6d delta;
  if (!state.partial_view && solveStep(state.equations.data(), static_cast<int>(state.equations.size()),
                                       state.x_accumulated, kOptimumDamping, delta))
    measured.applyCameraIncrement(delta);
  return measured;
}

void ImuPropagator::updateWithVision(EstimatorState& state)
{
  catchUp();
  cursor_.flushCovariance(ekf_);
  vision_covariance_ = visionPoseCovariance(state);
  const Pose measured = visionMeasurement(state);
  const double chi2 = ekf_.updateCameraPose(measured, vision_covariance_ * params_.vision_covariance_scale, kGate);
  ++stats_.updates;
  t_last_update_ = due_ns_;
  const bool rejected = !(chi2 <= kGate);
  if (rejected)
    ++stats_.updates_rejected;
  else
    stats_.nis_sum += chi2;
  // Agreement: the running mean of the normalised innovations squared, times the vision
  // covariance's scale (so that it does not depend on it; ~50 with a sound IMU, thousands with
  // wrong units, extrinsics or clock offset).
  nis_mean_ += ((rejected ? kGate : chi2) * params_.vision_covariance_scale - nis_mean_) * kNisAlpha;
  ++updates_since_restart_;
  // Biases far outside their prior: the filter is explaining a model error (a wrong gravity,
  // extrinsic or clock) with them, and the vision would follow it.
  const double bg = ekf_.gyroBias().norm(), ba = ekf_.accelBias().norm();
  if (bg > kBiasSigmas * params_.initial_gyro_bias_sigma ||
      (ba > kBiasSigmas * params_.initial_accel_bias_sigma && !gravityEstimated()))
  {
    // Vision alone, and the next start forgets what was learned.
    char buf[160];
    std::snprintf(buf, sizeof buf, "the estimated biases left their plausible range (gyro %.4f rad/s, accel %.3f m/s^2)",
                  bg, ba);
    setAside(ImuStatus::kDisagrees, std::string(buf) + ": a wrong extrinsic, clock offset or imu_gravity_world?",
             due_ns_, true);
    return;
  }
  if (ba > kBiasSigmas * params_.initial_accel_bias_sigma && ekf_.usesAccelerometer())
  {
    // A confirmed estimated gravity that the accelerometer bias has to make up for after all.
    ekf_.start(state.pose, cursor_.sample.accel, ImuEkf::Keep::kGyroBias);
    rejectGravity(ba);
  }
  checkGravity(measured);
  const bool agrees = !rejected && nis_mean_ < kAgreeNis;
  if (trusted_ && !agrees)
  {
    // Until the filter agrees with the vision again the IMU does not move the tracker's pose.
    trusted_ = false;
    checking_since_ns_ = due_ns_;
    setStatus(ImuStatus::kChecking, "the IMU's predictions disagree with the vision: checking again");
  }
  if (!trusted_)
  {
    if (rejected)
    {
      // Follow the vision.
      ekf_.start(state.pose, cursor_.sample.accel, ImuEkf::Keep::kAll);
      if (checking_gravity_)
        gravity_check_.start(state.pose, cursor_.sample.accel, ImuEkf::Keep::kAll);
    }
    if (agrees && updates_since_restart_ >= kTrustUpdates)
    {
      trusted_ = true;
      setFusedStatus();
    }
    else if (due_ns_ - checking_since_ns_ > kMaxCheckingNs)
    {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.0f", nis_mean_);
      setAside(ImuStatus::kDisagrees,
               std::string("the IMU's predictions disagreed with the vision for ") +
                   std::to_string(kMaxCheckingNs / 1000000) + " ms (mean scaled innovation " + buf +
                   ", agreement below " + std::to_string(int(kAgreeNis)) + "): wrong units, extrinsics or clock offset?",
               due_ns_);
    }
    return;
  }
  // The tracker continues from the filter's estimate.
  const Vector6d d = cameraIncrementBetween(state.pose, ekf_.cameraPose());
  state.pose.applyCameraIncrement(d);
  state.x_accumulated += d;
}

void ImuPropagator::setFusedStatus()
{
  if (gyro_only_)
    setStatus(ImuStatus::kGyroOnly, gyro_only_reason_);
  else if (checking_gravity_)
    setStatus(ImuStatus::kGyroOnly, kCheckingGravity);
  else
    setStatus(ImuStatus::kOk, "");
}

void ImuPropagator::rejectGravity(double accel_bias)
{
  checking_gravity_ = false;
  gravity_checked_ = false;
  gyro_only_ = true;
  ekf_.useAccelerometer(false);
  char buf[96];
  std::snprintf(buf, sizeof buf, "the estimated gravity made the accelerometer bias implausible (%.3f m/s^2)", accel_bias);
  gyro_only_reason_ = std::string(buf) + ": gyroscope only until the next start (give imu_gravity_world)";
  if (trusted_)
    setFusedStatus();
}

void ImuPropagator::checkGravity(const Pose& measured)
{
  if (!checking_gravity_)
    return;
  gravity_cursor_.flushCovariance(gravity_check_);  // its mean is at due_ns_ (catchUp)
  const double chi2 =
      gravity_check_.updateCameraPose(measured, vision_covariance_ * params_.vision_covariance_scale, kGate);
  const double ba = gravity_check_.accelBias().norm();
  if (ba > kBiasSigmas * params_.initial_accel_bias_sigma)
  {
    // The accelerometer bias has to make up for the gravity: it started from a specific force
    // that was not at rest (the camera accelerating), and the vision (at range, over a fraction
    // of a second) cannot tell a tilted gravity from its own slowly varying error. The gyroscope
    // is sound: the tracker's filter keeps running without the accelerometer until the next start.
    rejectGravity(ba);
    return;
  }
  if (chi2 <= kGate && due_ns_ - started_ns_ >= gravity_check_ns_ &&
      ba <= kCheckedBiasSigmas * params_.initial_accel_bias_sigma)
  {
    // Confirmed: the tracker's filter continues as the one with the accelerometer.
    ekf_ = gravity_check_;
    checking_gravity_ = false;
    gravity_checked_ = true;
    if (trusted_)
      setFusedStatus();
  }
}

void ImuPropagator::propagate(EstimatorState& state, int64_t t_ns)
{
  if (!tracking_)
  {
    // Start again (checked first) once trusted again and fresh.
    if (t_ns >= distrust_until_ns_ && newest_ns_ != INT64_MIN && t_ns - newest_ns_ <= max_latency_ns_)
      restart(state, t_ns);
    return;
  }
  if (newest_ns_ == INT64_MIN || t_ns - newest_ns_ > max_latency_ns_ || !isEngaged(status_))
  {
    tracking_ = false;
    trusted_ = false;
    if (isEngaged(status_))
      setStatus(ImuStatus::kLate, "no IMU sample within imu_max_latency of the events (stream missing or late)");
    return;
  }
  // The vision's pose is that of the previous event: compared only when the filter got there.
  if (due_ns_ - t_last_update_ >= update_period_ns_ && due_ns_ >= previous_event_ns_)
  {
    updateWithVision(state);
    if (!tracking_)
      return;
  }
  // Never beyond the newest sample by more than two sample periods: samples that arrive late
  // (another topic, a loaded machine) are then still integrated in order instead of being
  // skipped by a filter that held an old one across their interval.
  const int64_t hold_ns = std::max<int64_t>(2000000, static_cast<int64_t>(2e9 * sample_period_s_));
  const int64_t t_to = std::min(t_ns, newest_ns_ + hold_ns);
  previous_event_ns_ = t_ns;
  // Trusted, the tracker's pose moves with the filter.
  advanceTo(t_to, trusted_ ? &state : nullptr);
}

bool ImuPropagator::odometry(int64_t t_ns, ImuOdometry& out) const
{
  if (!tracking_ || !isFused(status_))
    return false;
  // A copy of the filter, carried through the samples not yet consumed (an event-free gap) to t.
  ImuEkf f = ekf_;
  Cursor c = cursor_;
  for (size_t k = 0; k < count_ && ring_[(head_ + k) % ring_.size()].t_ns <= t_ns; ++k)
  {
    const Sample& s = ring_[(head_ + k) % ring_.size()];
    if (s.t_ns < due_ns_)
      c.meanTo(f, due_ns_);  // as advanceTo: the held sample is in force until the filter's time
    c.next(f, s);
  }
  c.meanTo(f, t_ns);
  c.flushCovariance(f);
  const int64_t t = c.t_ns;
  const Sample& cur = c.sample;
  out.t_ns = std::max(t_ns, t);
  out.T_world_camera = f.cameraPose();
  out.velocity_world = f.cameraVelocityWorld(cur.gyro);
  out.angular_velocity_camera = f.cameraAngularVelocity(cur.gyro);
  // The filter's covariance, plus the part of the vision's error that does not average away.
  out.pose_covariance = f.cameraPoseCovariance() + vision_covariance_ * params_.vision_error_scale;
  out.velocity_covariance = f.cameraVelocityCovariance();
  out.angular_velocity_covariance = f.cameraAngularVelocityCovariance(sample_period_s_);
  return true;
}
}  // namespace dvs_line_tracker
