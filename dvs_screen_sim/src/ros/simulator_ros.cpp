#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/imu_msg.h>
#include <dvs_driver/param_table_ros.h>
#include <dvs_screen_sim/ros_conversions.h>
#include <dvs_screen_sim/simulator_params.h>
#include <dvs_screen_sim/simulator_ros.h>

#include <dvs_msgs/EventArray.h>

#include <chrono>

namespace dvs_screen_sim
{
SimulatorRos::SimulatorRos(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh)
{
  SimulatorParams p;
  dvs_driver::ParamTable table = simulatorParamTable(p);
  dvs_driver::loadRosParams(pnh_, table);
  const std::string& scenario = p.scenario;
  real_time_factor_ = p.real_time_factor;
  loop_ = p.loop;
  wall_clock_stamps_ = p.wall_clock_stamps;
  world_frame_ = p.world_frame;
  camera_frame_ = p.camera_frame;
  gt_frame_ = p.ground_truth_frame;
  start_delay_ = p.start_delay;
  wait_for_subscribers_ = p.wait_for_subscribers;
  const int seed = p.seed;
  const double duration = p.run.duration, packet_period = p.run.packet_period;
  config_ = resolveSimConfigFile(scenario, p.config_file, static_cast<uint64_t>(seed),
                                 duration > 0 ? std::optional<double>(duration) : std::nullopt);
  config_.packet_period = packet_period;
  // 1000 packets = 1 s of 1 ms packets: a subscriber in another process may lag that much
  // before roscpp drops the oldest packets.
  events_pub_ = nh_.advertise<dvs_msgs::EventArray>("dvs/events", 1000);
  info_pub_ = nh_.advertise<sensor_msgs::CameraInfo>("dvs/camera_info", 1, true);
  pose_pub_ = nh_.advertise<geometry_msgs::PoseStamped>("dvs/ground_truth/pose", 100);
  map_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("dvs/ground_truth/map", 1, true);
  imu_pub_ = nh_.advertise<sensor_msgs::Imu>("dvs/imu", 1000);
  tf_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  ROS_INFO("dvs_screen_sim: scenario %s, %.3f s, %dx%d, real_time_factor %.2f%s", scenario.c_str(),
           config_.duration, config_.camera.width(), config_.camera.height(), real_time_factor_,
           loop_ ? ", looping" : "");
  thread_ = std::thread(&SimulatorRos::run, this);
}

SimulatorRos::~SimulatorRos()
{
  stop_ = true;
  if (thread_.joinable())
    thread_.join();
}

void SimulatorRos::run()
{
  try
  {
    runLoop();
  }
  catch (const std::exception& e)
  {
    // ROS shutting down under a publisher, or a runtime error: end the thread, never terminate().
    if (!stop_ && !ros::isShuttingDown())
      ROS_ERROR("dvs_screen_sim: simulation stopped: %s", e.what());
  }
}

void SimulatorRos::runLoop()
{
  const auto trajectory = makeTrajectory(config_);
  EventSimulator sim(config_.camera, config_.scene, config_.events, config_.sampling, config_.seed);
  ImuSimulator imu(config_.imu, config_.seed);
  imu.setTimeRange(0.0, config_.duration);
  dvs_driver::ImuVector imu_samples;
  const double gyro_sigma = config_.imu.gyroSigma(), accel_sigma = config_.imu.accelSigma();
  const int64_t period_ns = static_cast<int64_t>(std::llround(config_.packet_period * 1e9));
  const double gt_period = 1.0 / config_.groundtruth_rate;
  sensor_msgs::CameraInfo info = dvs_calibration::toCameraInfoMsg(config_.camera, camera_frame_);
  dvs_driver::EventVector buffer;
  // Let consumers (tracker, recorder) connect first, so they see the run from its start.
  const auto delay_end = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                                std::chrono::duration<double>(start_delay_));
  while (!stop_ && ros::ok() && std::chrono::steady_clock::now() < delay_end)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (wait_for_subscribers_)
  {
    ROS_INFO("dvs_screen_sim: waiting for a subscriber on %s", events_pub_.getTopic().c_str());
    while (!stop_ && ros::ok() && events_pub_.getNumSubscribers() == 0)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  do
  {
    // Time base of this run: wall clock at start, or the configured offset.
    // The wall clock of the run starts with its time base: what sim.start() takes (rendering the
    // first view) delays the first packets, as a late driver would, but never shifts every
    // packet after the time of its events (a constant latency seen by every consumer).
    const ros::Time base = wall_clock_stamps_ ? ros::Time::now() : secondsToRosTime(0.0);
    const auto wall_start = std::chrono::steady_clock::now();
    const int64_t base_ns = dvs_driver::rosTimeToNs(base) + config_.time_offset_ns;
    map_pub_.publish(mapMarkers(config_.scene, base, world_frame_));
    sim.start(*trajectory, 0.0, base_ns);
    imu.restart();
    long gt_index = 0;
    double next_info = 0.0;
    for (int64_t k = 1; !stop_ && ros::ok() && !ros::isShuttingDown(); ++k)
    {
      const double t = std::min(config_.duration, static_cast<double>(k * period_ns) * 1e-9);
      buffer.clear();
      sim.advanceTo(t, buffer);
      if (t >= config_.duration)
        sim.flush(buffer);
      if (real_time_factor_ > 0)
        std::this_thread::sleep_until(wall_start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                       std::chrono::duration<double>(t / real_time_factor_)));
      if (!buffer.empty())
      {
        auto msg = dvs_driver::toMessage(buffer.data(), buffer.data() + buffer.size(),
                                         static_cast<uint32_t>(config_.camera.width()),
                                         static_cast<uint32_t>(config_.camera.height()), camera_frame_);
        events_pub_.publish(msg);
      }
      imu_samples.clear();
      imu.advanceTo(*trajectory, t, base_ns, imu_samples);
      for (const auto& s : imu_samples)
        imu_pub_.publish(dvs_driver::toImuMessage(s, camera_frame_, gyro_sigma, accel_sigma));
      for (; gt_index * gt_period <= t + 1e-12; ++gt_index)
      {
        const double tg = gt_index * gt_period;
        StampedPose sp{static_cast<double>(base_ns) * 1e-9 + tg, trajectory->poseAt(tg)};
        // Exact stamps: base (ns) + tg rounded to ns.
        const int64_t stamp_ns = base_ns + static_cast<int64_t>(std::llround(tg * 1e9));
        geometry_msgs::PoseStamped pose = toPoseStamped(sp, world_frame_);
        pose.header.stamp = dvs_driver::nsToRosTime(stamp_ns);
        pose_pub_.publish(pose);
        geometry_msgs::TransformStamped tf = toTransform(sp, world_frame_, gt_frame_);
        tf.header.stamp = pose.header.stamp;
        tf_->sendTransform(tf);
      }
      if (t >= next_info)
      {
        info.header.stamp = dvs_driver::nsToRosTime(base_ns + static_cast<int64_t>(std::llround(t * 1e9)));
        info_pub_.publish(info);
        next_info += 0.1;
      }
      if (t >= config_.duration)
        break;
    }
    if (!stop_ && ros::ok() && !ros::isShuttingDown())
      ROS_INFO("dvs_screen_sim: finished %.3f s of %s (%llu events)", config_.duration, config_.scenario.c_str(),
               static_cast<unsigned long long>(sim.stats().signal_events + sim.stats().noise_events));
  } while (loop_ && !stop_ && ros::ok() && !ros::isShuttingDown());
}
}  // namespace dvs_screen_sim
