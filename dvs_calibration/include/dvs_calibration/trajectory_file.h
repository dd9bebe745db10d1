#pragma once
// TUM trajectory files: one pose a line, `t tx ty tz qx qy qz qw` (seconds, metres, Hamilton
// quaternion), T_world_camera; lines starting with '#' and blank lines are comments. What
// rpg_trajectory_evaluation and evo read. The reader also takes comma-separated values (CSV,
// same column order, an optional non-numeric header line), so a file from a spreadsheet or a
// motion-capture export works as well.
#include <dvs_calibration/pose.h>

#include <cstdint>
#include <iosfwd>
#include <stdexcept>
#include <string>

namespace dvs_calibration
{
/// Thrown for unreadable or malformed trajectory files; the message names file and line.
class TrajectoryFileError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// What the reader requires of consecutive times: ground truth and trajectories to play must
/// strictly increase; a tracker's estimate may repeat a time (several pose updates on events
/// with the same time stamp) but never go back.
enum class TimeOrder
{
  StrictlyIncreasing,
  NonDecreasing,
};

/// Read a TUM (or CSV) trajectory. Quaternions are normalised (a norm far from 1, < 0.5 or
/// > 1.5, is an error). Throws TrajectoryFileError naming file and line for a line without
/// exactly 8 numbers, non-finite values, or times that break `order`.
Trajectory readTumTrajectory(const std::string& path, TimeOrder order = TimeOrder::StrictlyIncreasing);
Trajectory readTumTrajectory(std::istream& in, const std::string& name,
                                 TimeOrder order = TimeOrder::StrictlyIncreasing);

/// Write a TUM trajectory (times with 9 decimals, positions and quaternions with 9 significant
/// decimals). `header` (may be empty) is written as a '#' comment line first. Throws
/// TrajectoryFileError when the file cannot be written.
void writeTumTrajectory(const std::string& path, const Trajectory& poses, const std::string& header = "");
void writeTumTrajectory(std::ostream& out, const Trajectory& poses, const std::string& header = "");

/// Appends `v` in fixed notation with `decimals` (0-17) digits after the point, exactly as
/// printf("%.*f") writes it, but without its format parsing and locale (std::to_chars: a
/// trajectory of millions of poses is written several times faster).
void appendFixed(std::string& out, double v, int decimals);
/// Appends the exact decimal seconds of `t_ns` ("12.000000345", "-0.000000001").
void appendSeconds(std::string& out, int64_t t_ns);
}  // namespace dvs_calibration
