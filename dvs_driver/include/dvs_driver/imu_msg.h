#pragma once
// ImuSample <-> sensor_msgs/Imu (header-only; library dvs_driver_ros): the one conversion the
// simulator's node, its bags and any IMU reader use. Covariances from the sensor's discrete
// white-noise standard deviations (diagonal); no orientation (orientation_covariance[0] = -1,
// as the sensor_msgs/Imu documentation asks).
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/imu_sample.h>
#include <sensor_msgs/Imu.h>

#include <string>

namespace dvs_driver
{
/// `gyro_sigma` [rad/s] and `accel_sigma` [m/s^2]: the per-sample noise standard deviations
/// (0: unknown, covariance left all zero).
inline sensor_msgs::Imu toImuMessage(const ImuSample& s, const std::string& frame_id, double gyro_sigma,
                                     double accel_sigma)
{
  sensor_msgs::Imu m;
  m.header.stamp = nsToRosTime(s.t_ns);
  m.header.frame_id = frame_id;
  m.orientation.w = 1.0;
  m.orientation_covariance[0] = -1.0;
  m.angular_velocity.x = s.gyro[0];
  m.angular_velocity.y = s.gyro[1];
  m.angular_velocity.z = s.gyro[2];
  m.linear_acceleration.x = s.accel[0];
  m.linear_acceleration.y = s.accel[1];
  m.linear_acceleration.z = s.accel[2];
  for (int i = 0; i < 3; ++i)
  {
    m.angular_velocity_covariance[4 * i] = gyro_sigma * gyro_sigma;
    m.linear_acceleration_covariance[4 * i] = accel_sigma * accel_sigma;
  }
  return m;
}

inline ImuSample fromImuMessage(const sensor_msgs::Imu& m)
{
  ImuSample s;
  s.t_ns = rosTimeToNs(m.header.stamp);
  s.gyro[0] = m.angular_velocity.x;
  s.gyro[1] = m.angular_velocity.y;
  s.gyro[2] = m.angular_velocity.z;
  s.accel[0] = m.linear_acceleration.x;
  s.accel[1] = m.linear_acceleration.y;
  s.accel[2] = m.linear_acceleration.z;
  return s;
}
}  // namespace dvs_driver
