#pragma once
// The live software DVS (used by both simulator_node and dvs_screen_sim/SimulatorNodelet).
// Publishes (relative to the node's namespace, remappable):
//   dvs/events              dvs_msgs/EventArray, one packet per packet_period of simulated time
//   dvs/camera_info         sensor_msgs/CameraInfo (latched, re-sent every 0.1 s simulated)
//   dvs/ground_truth/pose   geometry_msgs/PoseStamped T_world_camera at groundtruth_rate
//   dvs/ground_truth/map    visualization_msgs/MarkerArray (latched)
//   dvs/imu                 sensor_msgs/Imu at imu.rate (frame camera_frame; imu_simulator.h)
//   /tf                     world -> dvs_gt at groundtruth_rate
// Private parameters: one table (simulator_params.h, printed in the package README; unknown
// names are warned about, bad values refused naming the parameter). The simulation runs in its
// own thread; the constructor returns at once.
#include <dvs_screen_sim/event_simulator.h>
#include <dvs_screen_sim/sim_config.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <atomic>
#include <memory>
#include <thread>

namespace dvs_screen_sim
{
class SimulatorRos
{
public:
  /// Reads and validates the parameters (throws std::invalid_argument naming the bad one) and
  /// starts the simulation thread.
  SimulatorRos(ros::NodeHandle nh, ros::NodeHandle pnh);
  ~SimulatorRos();

private:
  void run();
  void runLoop();

  ros::NodeHandle nh_, pnh_;
  SimConfig config_;
  double real_time_factor_ = 1.0;
  bool loop_ = false;
  bool wall_clock_stamps_ = true;
  double start_delay_ = 0.0;           ///< [s] wait before simulating
  bool wait_for_subscribers_ = false;  ///< wait for a subscriber on dvs/events before simulating
  std::string world_frame_, camera_frame_, gt_frame_;
  ros::Publisher events_pub_, info_pub_, pose_pub_, map_pub_, imu_pub_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};
}  // namespace dvs_screen_sim
