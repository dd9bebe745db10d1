#pragma once
// The ROS-free IMU sample every core library of the suite speaks (one home): what the event-file
// readers decode (AEDAT 2.0 DAVIS IMU6 records, AEDAT 4.0 IMUS streams), what imu.txt holds
// (imu_text_io.h) and what the software DVS's IMU generates (dvs_screen_sim/imu_simulator.h).
#include <cmath>
#include <cstdint>
#include <vector>

namespace dvs_driver
{
/// One 6-axis IMU sample in SI units, in the IMU's own axes.
struct ImuSample
{
  int64_t t_ns = 0;             ///< time stamp, nanoseconds (the same time base as the events)
  double accel[3] = {0, 0, 0};  ///< specific force (accelerometer), m/s^2: +9.81 upwards at rest
  double gyro[3] = {0, 0, 0};   ///< angular velocity (gyroscope), rad/s
  double temperature_c = NAN;   ///< sensor temperature, deg C (NaN: not given; imu.txt has none)
};

/// Field by field; two NaN temperatures are equal.
inline bool operator==(const ImuSample& a, const ImuSample& b)
{
  for (int i = 0; i < 3; ++i)
    if (a.accel[i] != b.accel[i] || a.gyro[i] != b.gyro[i])
      return false;
  return a.t_ns == b.t_ns &&
         (a.temperature_c == b.temperature_c || (std::isnan(a.temperature_c) && std::isnan(b.temperature_c)));
}
inline bool operator!=(const ImuSample& a, const ImuSample& b) { return !(a == b); }

using ImuVector = std::vector<ImuSample>;

/// Standard gravity (the unit `g` of accelerometer files), m/s^2.
constexpr double kStandardGravity = 9.80665;
}  // namespace dvs_driver
