#include <dvs_line_tracker/motion_lag.h>

#include <Eigen/Geometry>

namespace dvs_line_tracker
{
void MotionLag::record(int64_t t_ns, const Pose& pose, uint64_t events_attributed)
{
  Sample& s = ring_[head_];
  s.t_ns = t_ns;
  s.pose = pose;
  s.events_attributed = events_attributed;
  head_ = (head_ + 1) % kCapacity;
  count_ = count_ < kCapacity ? count_ + 1 : kCapacity;
  next_ns_ = t_ns + kSamplePeriodNs;
}

bool MotionLag::window(const Sample*& then, const Sample*& now) const
{
  then = now = nullptr;
  if (count_ < 2)
    return false;
  now = &ring_[(head_ + kCapacity - 1) % kCapacity];
  // The newest sample at least kRateWindowNs older than the latest.
  for (int back = 1; back < count_; ++back)
  {
    const Sample& s = ring_[(head_ + kCapacity - 1 - back) % kCapacity];
    if (now->t_ns - s.t_ns >= kRateWindowNs)
    {
      then = &s;
      break;
    }
  }
  return then && now->t_ns - then->t_ns <= kMaxRateWindowNs && now->events_attributed > then->events_attributed;
}

double MotionLag::eventsPerSecond(const Sample& then, const Sample& now)
{
  return static_cast<double>(now.events_attributed - then.events_attributed) / ((now.t_ns - then.t_ns) * 1e-9);
}

double MotionLag::attributedRate() const
{
  const Sample *then, *now;
  return window(then, now) ? eventsPerSecond(*then, *now) : -1;
}

bool MotionLag::motion(int visible_segments, int buffer_size, double& angular_speed, double& linear_speed,
                       double& span_s) const
{
  angular_speed = linear_speed = span_s = 0;
  const Sample *then, *now;
  if (visible_segments <= 0 || buffer_size <= 0 || !window(then, now))
    return false;
  const double dt = (now->t_ns - then->t_ns) * 1e-9;
  const Eigen::AngleAxisd turn(now->pose.R_camera_world * then->pose.R_world_camera());
  angular_speed = std::abs(turn.angle()) / dt;
  linear_speed = (now->pose.p_world_camera() - then->pose.p_world_camera()).norm() / dt;
  span_s = static_cast<double>(buffer_size) * visible_segments / eventsPerSecond(*then, *now);
  return true;
}

Matrix6d MotionLag::covariance(int visible_segments, int buffer_size) const
{
  Matrix6d c = Matrix6d::Zero();
  double w = 0, v = 0, span = 0;
  if (!motion(visible_segments, buffer_size, w, v, span))
    return c;
  const double rotation_sd = w * span / 2, position_sd = v * span / 2;
  c.diagonal().head<3>().setConstant(rotation_sd * rotation_sd);
  c.diagonal().tail<3>().setConstant(position_sd * position_sd);
  return c;
}
}  // namespace dvs_line_tracker
