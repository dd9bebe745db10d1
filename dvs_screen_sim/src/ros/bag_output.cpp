#include <dvs_driver/event_bag_io.h>
#include <dvs_screen_sim/bag_output.h>
#include <dvs_screen_sim/ros_conversions.h>
#include <dvs_driver/checked_bag.h>
#include <dvs_driver/imu_msg.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>

namespace dvs_screen_sim
{
namespace
{
ros::Time recordTime(const ros::Time& t)
{
  return std::max(t, ros::TIME_MIN);
}
}  // namespace

// Every bag write goes through the checked writer: a full disk or a missing folder is a
// BagWriteError naming the bag, never an abort from rosbag.
SimulationBagWriter::SimulationBagWriter(const std::string& path, const SimConfig& config)
  : config_(config), bag_(std::make_unique<dvs_driver::CheckedBagWriter>(path))
{
}

SimulationBagWriter::~SimulationBagWriter() = default;

void SimulationBagWriter::addEvents(const dvs_driver::EventVector& chunk)
{
  const auto period_ns = static_cast<int64_t>(std::llround(config_.packet_period * 1e9));
  dvs_driver::writeEventsBag(*bag_, "/dvs/events", chunk, static_cast<uint32_t>(config_.camera.width()),
                             static_cast<uint32_t>(config_.camera.height()), period_ns, "dvs");
}

void SimulationBagWriter::finish(const dvs_calibration::Trajectory& groundtruth, const dvs_driver::ImuVector& imu)
{
  const double t0 = static_cast<double>(config_.time_offset_ns) * 1e-9;
  const double t_end = t0 + config_.duration;
  sensor_msgs::CameraInfo info = dvs_calibration::toCameraInfoMsg(config_.camera, "dvs");
  for (long i = 0;; ++i)
  {
    const double t = t0 + 0.1 * static_cast<double>(i);
    if (t > t_end + 1e-9)
      break;
    info.header.stamp = secondsToRosTime(t);
    bag_->write("/dvs/camera_info", recordTime(info.header.stamp), info);
  }
  for (long i = 0;; ++i)
  {
    const double t = t0 + static_cast<double>(i);
    if (t > t_end + 1e-9)
      break;
    const ros::Time stamp = secondsToRosTime(t);
    bag_->write("/dvs/ground_truth/map", recordTime(stamp), mapMarkers(config_.scene, stamp, "world"));
  }
  for (const auto& sp : groundtruth)
  {
    const geometry_msgs::PoseStamped pose = toPoseStamped(sp, "world");
    bag_->write("/dvs/ground_truth/pose", recordTime(pose.header.stamp), pose);
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(toTransform(sp, "world", "dvs_gt"));
    bag_->write("/tf", recordTime(pose.header.stamp), tf);
  }
  for (const auto& s : imu)
  {
    const sensor_msgs::Imu m = dvs_driver::toImuMessage(s, "dvs", config_.imu.gyroSigma(), config_.imu.accelSigma());
    bag_->write("/dvs/imu", recordTime(m.header.stamp), m);
  }
  bag_->close();
}

void writeSimulationBag(const std::string& path, const SimConfig& config, const SimulationOutput& output)
{
  SimulationBagWriter writer(path, config);
  writer.addEvents(output.events);
  writer.finish(output.groundtruth, output.imu);
}
}  // namespace dvs_screen_sim
