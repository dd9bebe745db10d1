#include <dvs_screen_sim/screen_loop_ros.h>

#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/param_table_ros.h>
#include <dvs_screen_sim/ros_conversions.h>
#include <dvs_screen_sim/screen_loop/window_screen.h>
#include <dvs_driver/checked_bag.h>
#include <tf2_msgs/TFMessage.h>

namespace dvs_screen_sim
{
using namespace screen_loop;

ScreenLoopRos::ScreenLoopRos(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh)
{
  dvs_driver::ParamTable table = screenLoopParamTable(params_);
  dvs_driver::loadRosParams(pnh_, table);
  config_ = resolveSimConfigFile(params_.scenario, params_.config_file);
  trajectory_ = makeTrajectory(config_);
  if (!params_.calibration_file.empty())
    camera_ = dvs_calibration::loadCameraFile(params_.calibration_file, config_.camera.width(), config_.camera.height());
  else
  {
    camera_ = config_.camera;
    ROS_WARN("screen_loop: no ~calibration_file: using the configuration's camera (%dx%d, fx %.1f): calibrate the "
             "DVS first (dvs_calibration) for an accurate alignment",
             camera_.width(), camera_.height(), camera_.intrinsics().fx);
  }
  sub_ = nh_.subscribe("dvs/events", 100, &ScreenLoopRos::onEvents, this);
  pose_pub_ = nh_.advertise<geometry_msgs::PoseStamped>("dvs/ground_truth/pose", 100);
}

void ScreenLoopRos::onEvents(const dvs_msgs::EventArray::ConstPtr& msg)
{
  const int64_t arrival = hostNowNs();
  packet_.clear();
  dvs_driver::appendFromMessage(*msg, packet_);
  events_.addPacket(packet_.data(), packet_.data() + packet_.size(), arrival);
}

int ScreenLoopRos::run()
{
  ros::AsyncSpinner spinner(1);  // the events' callback (one thread: packet_ is its own)
  spinner.start();
  WindowConfig wc;
  wc.fullscreen = params_.fullscreen;
  wc.width = params_.width;
  wc.height = params_.height;
  GlScreenRenderer gl(wc);
  WindowScreen screen(gl, [] { return ros::ok(); });
  const double period = screen.measureRefreshPeriod(params_.refresh_measurement_frames);
  ROS_INFO("screen_loop: %dx%d window, refresh period %.2f ms%s", gl.width(), gl.height(), period * 1e3,
           gl.vsyncEnabled() ? "" : " (no vsync: this is the render time, not the screen's refresh)");
  ScreenLoopProcedure procedure(procedureConfig(params_), camera_, screen, events_,
                                [](LogLevel level, const std::string& m) {
                                  if (level == LogLevel::Info)
                                    ROS_INFO("screen_loop: %s", m.c_str());
                                  else if (level == LogLevel::Warn)
                                    ROS_WARN("screen_loop: %s", m.c_str());
                                  else
                                    ROS_ERROR("screen_loop: %s", m.c_str());
                                });
  if (!procedure.align().ok)
    return 1;
  const std::string warn =
      motionWarning(procedure.checkMotion(config_.scene, *trajectory_, config_.duration, TimeScale{params_.time_scale}));
  if (!warn.empty())
    ROS_WARN("screen_loop: %s", warn.c_str());
  const Playback playback = procedure.play(
      config_.scene, *trajectory_, config_.duration, TimeScale{params_.time_scale},
      [this](const StampedPose& live) {
        pose_pub_.publish(toPoseStamped(live, params_.world_frame));
        tf_.sendTransform(toTransform(live, params_.world_frame, params_.ground_truth_frame));
      },
      !params_.bag.empty());
  if (!params_.bag.empty())
    writeBag(playback);
  ROS_INFO("screen_loop: playback finished");
  return 0;
}

void ScreenLoopRos::writeBag(const Playback& playback) const
{
  // Events and ground truth in trajectory time, from the playback's start in the DVS's time base.
  const int64_t start = playback.start_dvs_ns;
  dvs_driver::EventVector events = playback.events;
  for (auto& e : events)
    e.t_ns += start;
  dvs_driver::CheckedBagWriter bag(params_.bag);  // throws BagWriteError naming the bag
  dvs_driver::writeEventsBag(bag, "/dvs/events", events, static_cast<uint32_t>(camera_.width()),
                             static_cast<uint32_t>(camera_.height()));
  for (StampedPose sp : playback.shown)
  {
    sp.t += start * 1e-9;
    const auto msg = toPoseStamped(sp, params_.world_frame);
    bag.write("/dvs/ground_truth/pose", msg.header.stamp, msg);
    tf2_msgs::TFMessage tfm;
    tfm.transforms.push_back(toTransform(sp, params_.world_frame, params_.ground_truth_frame));
    bag.write("/tf", msg.header.stamp, tfm);
  }
  const auto info = dvs_calibration::toCameraInfoMsg(camera_, "dvs");
  bag.write("/dvs/camera_info", secondsToRosTime(start * 1e-9), info);
  bag.close();
  ROS_INFO("screen_loop: recorded %zu events and %zu poses to %s", events.size(), playback.shown.size(),
           params_.bag.c_str());
}
}  // namespace dvs_screen_sim
