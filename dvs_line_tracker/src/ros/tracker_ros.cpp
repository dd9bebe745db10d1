#include <dvs_line_tracker/tracker_params.h>
#include <dvs_line_tracker/tracker_ros.h>
#include <dvs_calibration/camera_info_conversions.h>

#include <cv_bridge/cv_bridge.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/imu_msg.h>
#include <dvs_driver/param_table_ros.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <opencv2/imgproc.hpp>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>

#include <stdexcept>
#include <vector>

namespace dvs_line_tracker
{
namespace
{
/// Appended to the state (~state, the diagnostics' message) while a partial view is held.
const char* const kPartialViewHeldNote = ": partial view held (a corner only in view), no pose";

geometry_msgs::Pose toPoseMsg(const Pose& pose)
{
  geometry_msgs::Pose p;
  const Eigen::Vector3d t = pose.p_world_camera();
  const Eigen::Quaterniond q = pose.q_world_camera();
  p.position.x = t.x();
  p.position.y = t.y();
  p.position.z = t.z();
  p.orientation.x = q.x();
  p.orientation.y = q.y();
  p.orientation.z = q.z();
  p.orientation.w = q.w();
  return p;
}
}  // namespace

// Diagnostics under the tracker's own name (a nodelet's node name is its manager's).
TrackerRos::TrackerRos(ros::NodeHandle nh, ros::NodeHandle pnh)
  : nh_(nh), pnh_(pnh), diagnostics_(nh, pnh, pnh.getNamespace())
{
  // Every parameter in one table (the tracker's and the node's own): defaults, ROS overrides,
  // unknown names warned about, bounds validated (throws naming the parameter).
  std::string solver = solverTypeName(params_.estimator.solver);
  dvs_driver::ParamTable table = trackerParamTable(params_, solver);
  table.merge(nodeParamTable(settings_));
  dvs_driver::loadRosParams(pnh_, table);
  applySolverName(solver, params_);
  map_ = settings_.map_file.empty() ? defaultSquareMap() : loadLineMap(settings_.map_file);  // throws naming the file

  parseBodyCameraExtrinsic(settings_.q_body_camera, settings_.p_body_camera, T_camera_body_);  // validated above
  if (settings_.body_frame.empty())
    settings_.body_frame = settings_.camera_frame;
  pose_pub_ = pnh_.advertise<geometry_msgs::PoseStamped>("pose", 10000);
  odometry_pub_ = pnh_.advertise<nav_msgs::Odometry>("odometry", 1000);
  poses_pub_ = pnh_.advertise<nav_msgs::Path>("poses", 1000);
  markers_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>("markers", 1, true);
  state_pub_ = pnh_.advertise<std_msgs::String>("state", 10, true);
  image_transport::ImageTransport it(pnh_);
  image_pub_ = it.advertise("image", 1);

  diagnostics_.setHardwareID("dvs_line_tracker");
  diagnostics_.add("tracker", this, &TrackerRos::diagnose);
  // The tracking thread updates the diagnostics with mutex_ held, and diagnose() takes mutex_
  // inside the updater's own lock: the timer takes mutex_ first too (one lock order, see the
  // header), or the two threads deadlock (each holding the lock the other waits for).
  diagnostics_timer_ = nh_.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    diagnostics_.update();
  });

  if (!settings_.calibration_file.empty())
  {
    // A camera_info YAML has its size; ~width/~height are for a calib.txt.
    const std::string& file = settings_.calibration_file;
    const bool yaml = dvs_calibration::isCameraInfoYamlPath(file);
    startTracker(dvs_calibration::loadCameraFile(file, yaml ? 0 : settings_.width, yaml ? 0 : settings_.height));
  }
  else
    camera_info_sub_ = nh_.subscribe("dvs/camera_info", 1, &TrackerRos::onCameraInfo, this);
  events_sub_ = nh_.subscribe("dvs/events", 1000, &TrackerRos::onEvents, this, ros::TransportHints().tcpNoDelay());
  if (settings_.use_imu)
    imu_sub_ = nh_.subscribe("dvs/imu", 1000, &TrackerRos::onImu, this, ros::TransportHints().tcpNoDelay());
  OverloadParams overload;
  overload.max_latency_s = settings_.overload_latency_s;
  overload.max_queued_events = static_cast<size_t>(settings_.max_queued_events);
  overload_ = OverloadGovernor(overload);
  tracking_thread_ = std::thread(&TrackerRos::trackingLoop, this);
  if (settings_.output_rate_hz > 0)
  {
    // Its own queue and thread: a steady stream, not queued behind the event packets' callbacks.
    ros::TimerOptions options(ros::Duration(1.0 / settings_.output_rate_hz),
                              boost::bind(&TrackerRos::onOutputTimer, this, boost::placeholders::_1), &output_queue_);
    output_timer_ = nh_.createTimer(options);
    output_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &output_queue_);
    output_spinner_->start();
  }
  std_msgs::String state;
  state.data = toString(TrackerState::kInitializing);
  state_pub_.publish(state);
}

TrackerRos::~TrackerRos()
{
  // The output thread first: its timer callback uses everything else.
  output_timer_.stop();
  if (output_spinner_)
    output_spinner_->stop();
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (tracking_thread_.joinable())
    tracking_thread_.join();
}

void TrackerRos::startTracker(const dvs_calibration::CameraModel& camera)
{
  tracker_ = std::make_unique<LineTracker>(camera, map_, params_);
  if (settings_.use_imu)
  {
    imu_ = std::make_shared<ImuPropagator>(params_.imu);
    tracker_->setPropagator(imu_);
  }
  tracker_ready_ = true;
  ROS_INFO("dvs_line_tracker: tracking %zu segments (%zu polygons) with a %dx%d camera", map_.segments.size(),
           map_.polygons.size(), camera.width(), camera.height());
}

void TrackerRos::onCameraInfo(const sensor_msgs::CameraInfoConstPtr& msg)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (tracker_)
    return;
  try
  {
    startTracker(dvs_calibration::cameraFromCameraInfo(*msg));
    camera_info_sub_.shutdown();
  }
  catch (const std::exception& e)
  {
    ROS_ERROR_THROTTLE(5.0, "dvs_line_tracker: unusable camera_info: %s", e.what());
  }
}

void TrackerRos::onImu(const sensor_msgs::ImuConstPtr& msg)
{
  {
    std::lock_guard<std::recursive_mutex> lock(mutex_);
    ++imu_messages_;
    if (!imu_)
      return;
    imu_->addSample(dvs_driver::fromImuMessage(*msg));
  }
  {
    std::lock_guard<std::mutex> q(queue_mutex_);  // no wake-up lost between the check and the wait
  }
  wake_.notify_one();
}

void TrackerRos::onOutputTimer(const ros::TimerEvent&)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (!tracker_ || tracker_->state() != TrackerState::kTracking || last_event_ns_ == INT64_MIN)
    return;
  // Predicted to the publish time; the clock must be the events' (a replay needs use_sim_time):
  // never extrapolated beyond imu_max_latency past the last event.
  const int64_t now = static_cast<int64_t>(ros::Time::now().toNSec());
  const int64_t horizon = static_cast<int64_t>(params_.imu.max_latency_s * 1e9);
  int64_t t = now;
  if (now < last_event_ns_ || now - last_event_ns_ > horizon)
  {
    if (std::llabs(now - last_event_ns_) > 1000000000LL)
      ROS_WARN_THROTTLE(10.0, "dvs_line_tracker: ~output_rate: the clock is %.1f s away from the events' time stamps "
                              "(replaying without use_sim_time?): odometry stamped with the last event's time",
                        (now - last_event_ns_) * 1e-9);
    t = now < last_event_ns_ ? last_event_ns_ : last_event_ns_ + horizon;
  }
  publishOdometry(t);
}

void TrackerRos::publishOdometry(int64_t t_ns)
{
  if (odometry_pub_.getNumSubscribers() == 0 || !tracker_ || tracker_->state() != TrackerState::kTracking)
    return;
  ImuOdometry o;
  const bool fused = imu_ && imu_->odometry(t_ns, o);
  if (fused)
    o.pose_covariance += tracker_->motionLagCovariance();  // the vision updates' lag (motion_lag.h)
  const BodyOdometry b =
      fused
          ? toBodyOdometry(o, T_camera_body_)
          : visionBodyOdometry(last_event_ns_, tracker_->pose(), tracker_->visionOnlyPoseCovariance(), T_camera_body_);
  if (b.t_ns < last_odometry_ns_)
    return;  // switching between the IMU's prediction and the vision's pose: stamps never go back
  last_odometry_ns_ = b.t_ns;
  nav_msgs::OdometryPtr m = boost::make_shared<nav_msgs::Odometry>();
  m->header.stamp.fromNSec(static_cast<uint64_t>(b.t_ns));
  m->header.frame_id = settings_.world_frame;
  m->child_frame_id = settings_.body_frame;
  m->pose.pose = toPoseMsg(b.T_world_body);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c)
    {
      m->pose.covariance[r * 6 + c] = b.pose_covariance(r, c);
      m->twist.covariance[r * 6 + c] = b.twist_covariance(r, c);
    }
  m->twist.twist.linear.x = b.linear_velocity_body.x();
  m->twist.twist.linear.y = b.linear_velocity_body.y();
  m->twist.twist.linear.z = b.linear_velocity_body.z();
  m->twist.twist.angular.x = b.angular_velocity_body.x();
  m->twist.twist.angular.y = b.angular_velocity_body.y();
  m->twist.twist.angular.z = b.angular_velocity_body.z();
  odometry_pub_.publish(m);
}

void TrackerRos::onEvents(const dvs_msgs::EventArrayConstPtr& msg)
{
  if (!tracker_ready_.load())
  {
    ROS_WARN_THROTTLE(5.0, "dvs_line_tracker: no camera calibration yet (waiting for dvs/camera_info): events dropped");
    return;
  }
  {
    std::lock_guard<std::mutex> q(queue_mutex_);
    pending_.push_back({msg, ros::WallTime::now(), ros::Time::now()});
    pending_events_ += msg->events.size();
    // Memory stays bounded whatever comes in: the oldest packets go first (counted, warned).
    while (pending_.size() > 1 && overload_.overQueueLimit(pending_events_))
    {
      const size_t n = pending_.front().msg->events.size();
      overload_.dropped(n);
      pending_events_ -= n;
      pending_.pop_front();
    }
  }
  wake_.notify_one();
}

bool TrackerRos::nextPacket(PendingPacket& packet)
{
  // Events and IMU samples come on two topics, and either may arrive first: while the IMU is
  // used, a packet waits until the IMU has reached its last event, so that the IMU carries the
  // pose to each event with the samples of its time. It waits in data time (the packets behind
  // it reach imu_max_latency past the newest IMU sample: the IMU is late), not wall time (a
  // tracker behind real time would find every sample late), and at most 1 s of wall time (the
  // event stream stopped).
  if (pending_.empty())
    return false;
  const int64_t max_latency_ns = static_cast<int64_t>(params_.imu.max_latency_s * 1e9);
  const auto endOf = [](const dvs_msgs::EventArray& m) {
    return m.events.empty() ? INT64_MIN : dvs_driver::rosTimeToNs(m.events.back().ts);
  };
  const auto& p = pending_.front();
  const bool imu_used = imu_ && isEngaged(imu_->status());
  const int64_t end_ns = endOf(*p.msg);
  const int64_t newest_event_ns = std::max(end_ns, endOf(*pending_.back().msg));  // an empty last packet: no time
  if (imu_used && end_ns != INT64_MIN && imu_->newestSampleNs() < end_ns &&
      newest_event_ns - imu_->newestSampleNs() <= max_latency_ns &&
      ros::WallTime::now() - p.arrival < ros::WallDuration(1.0))
    return false;
  queue_wait_max_s_ = std::max(queue_wait_max_s_, (ros::WallTime::now() - p.arrival).toSec());
  packet = p;
  pending_events_ -= packet.msg->events.size();
  pending_.pop_front();
  return true;
}

void TrackerRos::trackingLoop()
{
  for (;;)
  {
    // Between packets the IMU callback and ~output_rate's thread get the tracker's lock.
    std::unique_lock<std::recursive_mutex> lock(mutex_);
    PendingPacket packet;
    int stride = 1;
    bool initialising = false;
    {
      std::unique_lock<std::mutex> q(queue_mutex_);
      if (stopping_)
        return;
      if (!nextPacket(packet))
      {
        // A packet or an IMU sample wakes it; the timeout tracks a packet whose IMU stopped.
        lock.unlock();
        wake_.wait_for(q, std::chrono::milliseconds(100));
        continue;
      }
      // Initialising: whole packets or none (the detection needs dense edges).
      initialising = tracker_ && tracker_->state() != TrackerState::kTracking;
      stride = overload_.strideFor(pending_events_ + packet.msg->events.size(), initialising);
      if (initialising && stride > 1)
      {
        if (overload_.skipWholePacket(stride, packet.msg->events.size()))
        {
          reportOverload();
          continue;
        }
        stride = 1;
      }
    }
    const dvs_msgs::EventArrayConstPtr& msg = packet.msg;
    double seconds = 0;
    const size_t tracked = processPacket(packet, stride, ros::WallTime::now(), &seconds);
    std::lock_guard<std::mutex> q(queue_mutex_);
    overload_.tracked(tracked, seconds, initialising);
    if (tracked < msg->events.size())
      overload_.skipped(msg->events.size() - tracked);
    reportOverload();
  }
}

size_t TrackerRos::processPacket(const PendingPacket& packet, int stride, ros::WallTime start, double* event_loop_s)
{
  const auto loop_start = std::chrono::steady_clock::now();
  const dvs_msgs::EventArrayConstPtr& msg = packet.msg;
  const bool per_event = settings_.publish_per_event_poses && pose_pub_.getNumSubscribers() > 0;
  const bool batched = poses_pub_.getNumSubscribers() > 0;
  nav_msgs::PathPtr poses;
  if (batched)
  {
    poses = boost::make_shared<nav_msgs::Path>();
    poses->header.frame_id = settings_.world_frame;
    poses->poses.reserve(msg->events.size());
  }
  int64_t last_update_ns = 0;
  bool any_update = false;
  dvs_driver::Event e;
  size_t tracked = 0;
  for (const auto& m : msg->events)
  {
    if (stride > 1 && stride_phase_++ % static_cast<uint64_t>(stride) != 0)
      continue;
    ++tracked;
    e.t_ns = dvs_driver::rosTimeToNs(m.ts);
    e.x = m.x;
    e.y = m.y;
    e.polarity = m.polarity;
    if (!tracker_->processEvent(e))
      continue;
    any_update = true;
    last_update_ns = e.t_ns;
    ++updates_since_diag_;
    if (per_event)
    {
      geometry_msgs::PoseStampedPtr p = boost::make_shared<geometry_msgs::PoseStamped>();
      p->header.stamp = m.ts;
      p->header.frame_id = settings_.world_frame;
      p->pose = toPoseMsg(tracker_->pose());
      pose_pub_.publish(p);
    }
    if (batched)
    {
      poses->poses.emplace_back();
      geometry_msgs::PoseStamped& p = poses->poses.back();
      p.header.stamp = m.ts;
      p.header.frame_id = settings_.world_frame;
      p.pose = toPoseMsg(tracker_->pose());
    }
  }
  const ros::WallTime processed = ros::WallTime::now();
  // The time the stride can shorten: the tracked events and their outputs. (The packet's own
  // outputs and bookkeeping below do not shrink with the stride; counted per tracked event, they
  // made a high stride look costlier per event and raised it further.)
  if (event_loop_s)
    *event_loop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count();
  events_since_diag_ += msg->events.size();
  if (!msg->events.empty())
    last_event_ns_ = dvs_driver::rosTimeToNs(msg->events.back().ts);
  reportInputProblems();
  if (settings_.output_rate_hz <= 0 && any_update)
    publishOdometry(last_update_ns);
  if (batched && !poses->poses.empty())
  {
    poses->header.stamp = poses->poses.back().header.stamp;
    poses_pub_.publish(poses);
  }
  publishPacket(*msg, last_update_ns, any_update);
  if (!msg->events.empty())
  {
    // The latency of every event of the packet, in parts (latency_split.h).
    PacketTiming t;
    t.last_event_ns = last_event_ns_;
    t.arrival_clock_ns = dvs_driver::rosTimeToNs(packet.arrival_clock);
    t.queue_s = (start - packet.arrival).toSec();
    t.processing_s = (processed - start).toSec();
    t.publishing_s = (ros::WallTime::now() - processed).toSec();
    t.events = msg->events.size();
    latency_.beginPacket(t);
    for (const auto& m : msg->events)
      latency_.addEvent(dvs_driver::rosTimeToNs(m.ts));
  }
  diagnostics_.update();
  return tracked;
}

void TrackerRos::reportOverload()
{
  const OverloadStats& o = overload_.stats();
  if (o.events_skipped > skipped_reported_ || o.events_dropped > dropped_reported_)
  {
    ROS_WARN_THROTTLE(1.0,
                      "dvs_line_tracker: falling behind the events: tracking every %d-th event (every %d-th packet "
                      "while initialising; %llu skipped, with %llu packets skipped whole; %llu dropped with %llu "
                      "packets over max_queued_events so far; overload_latency %.3f s)",
                      o.last_stride, o.last_stride, static_cast<unsigned long long>(o.events_skipped),
                      static_cast<unsigned long long>(o.packets_skipped),
                      static_cast<unsigned long long>(o.events_dropped),
                      static_cast<unsigned long long>(o.packets_dropped), overload_.params().max_latency_s);
    skipped_reported_ = o.events_skipped;
    dropped_reported_ = o.events_dropped;
  }
}

void TrackerRos::reportInputProblems()
{
  // Dropped or repaired input is never silent: a warning at most once per second, and the
  // counters in diagnostics (WARN while non-zero).
  const auto& st = tracker_->stats();
  if (st.events_outside_sensor > reported_outside_)
  {
    ROS_WARN_THROTTLE(1.0, "dvs_line_tracker: %llu events outside the %dx%d sensor ignored so far (wrong camera_info or "
                           "calibration size?)",
                      static_cast<unsigned long long>(st.events_outside_sensor), tracker_->camera().width(),
                      tracker_->camera().height());
    reported_outside_ = st.events_outside_sensor;
  }
  if (st.time_jumps > reported_time_jumps_)
  {
    ROS_WARN("dvs_line_tracker: %s", tracker_->lastLossReason().c_str());
    reported_time_jumps_ = st.time_jumps;
  }
  if (imu_ && imu_->statusMessage() != reported_imu_message_)
  {
    // The IMU fell back to vision alone (or came back): said once per change.
    reported_imu_message_ = imu_->statusMessage();
    if (imu_->status() == ImuStatus::kOk)
      ROS_INFO("dvs_line_tracker: IMU fused");
    else if (imu_->gravityRejected())
      ROS_WARN("dvs_line_tracker: IMU fused without the accelerometer: %s", reported_imu_message_.c_str());
    else if (imu_->status() == ImuStatus::kGyroOnly)
      ROS_INFO("dvs_line_tracker: IMU fused, %s", reported_imu_message_.c_str());
    else if (isSetAside(imu_->status()))
      ROS_WARN("dvs_line_tracker: IMU not used, vision alone (%s): %s", toString(imu_->status()),
               reported_imu_message_.c_str());
  }
}

void TrackerRos::publishPacket(const dvs_msgs::EventArray& msg, int64_t last_update_ns, bool any_update)
{
  if (tracker_->state() != last_state_ || tracker_->partialViewHeld() != last_held_)
  {
    const bool state_changed = tracker_->state() != last_state_;
    last_state_ = tracker_->state();
    last_held_ = tracker_->partialViewHeld();
    std_msgs::String state;
    state.data = toString(last_state_);
    if (last_state_ == TrackerState::kLost)
      state.data += ": " + tracker_->lastLossReason();
    if (last_held_)
      state.data += kPartialViewHeldNote;
    state_pub_.publish(state);
    // A held partial view lasts at most partial_view_grace_s: ~state and the diagnostics'
    // counters say so, the log does not (a chaotic flip can hold several a second).
    if (state_changed)
    {
      if (last_state_ == TrackerState::kLost)
        ROS_WARN("dvs_line_tracker: track lost (%s), re-initialising", tracker_->lastLossReason().c_str());
      else
        ROS_INFO("dvs_line_tracker: %s", toString(last_state_));
      diagnostics_.force_update();
    }
  }
  if (any_update && tracker_->state() == TrackerState::kTracking)
  {
    geometry_msgs::TransformStamped tf;
    tf.header.stamp.fromNSec(static_cast<uint64_t>(last_update_ns));
    tf.header.frame_id = settings_.world_frame;
    tf.child_frame_id = settings_.camera_frame;
    const geometry_msgs::Pose p = toPoseMsg(tracker_->pose());
    tf.transform.translation.x = p.position.x;
    tf.transform.translation.y = p.position.y;
    tf.transform.translation.z = p.position.z;
    tf.transform.rotation = p.orientation;
    tf_.sendTransform(tf);
  }
  const ros::Time stamp = msg.events.empty() ? msg.header.stamp : msg.events.back().ts;
  if (markers_pub_.getNumSubscribers() > 0 && (stamp - last_markers_).toSec() >= 1.0 / settings_.marker_rate_hz)
  {
    last_markers_ = stamp;
    publishMarkers(stamp);
  }
  if (image_pub_.getNumSubscribers() > 0 && (stamp - last_image_).toSec() >= 1.0 / settings_.image_rate_hz)
  {
    last_image_ = stamp;
    publishImage(msg);
  }
}

void TrackerRos::publishMarkers(const ros::Time& stamp)
{
  visualization_msgs::MarkerArrayPtr arr = boost::make_shared<visualization_msgs::MarkerArray>();
  visualization_msgs::Marker map_marker;
  map_marker.header.frame_id = settings_.world_frame;
  map_marker.header.stamp = stamp;
  map_marker.ns = "map";
  map_marker.type = visualization_msgs::Marker::LINE_LIST;
  map_marker.scale.x = 0.02;
  map_marker.color.g = map_marker.color.a = 1.0;
  map_marker.pose.orientation.w = 1.0;
  for (const auto& s : map_.segments)
    for (const auto* p : {&s.p0_world, &s.p1_world})
    {
      geometry_msgs::Point pt;
      pt.x = p->x();
      pt.y = p->y();
      pt.z = p->z();
      map_marker.points.push_back(pt);
    }
  arr->markers.push_back(map_marker);
  // Projected segments as lines on the camera's normalised image plane (z = 1 m in the dvs frame).
  visualization_msgs::Marker proj = map_marker;
  proj.header.frame_id = settings_.camera_frame;
  proj.ns = "projected_segments";
  proj.id = 1;
  proj.points.clear();
  proj.scale.x = 0.005;
  proj.color.g = 0;
  proj.color.r = 1.0;
  const PinholeK& k = tracker_->intrinsics();
  if (tracker_->state() == TrackerState::kTracking)
    for (const auto& s : tracker_->projectedSegments())
      for (const auto* p : {&s.a, &s.b})
      {
        geometry_msgs::Point pt;
        pt.x = (p->x() - k.cx) / k.fx;
        pt.y = (p->y() - k.cy) / k.fy;
        pt.z = 1.0;
        proj.points.push_back(pt);
      }
  if (proj.points.empty())
    proj.action = visualization_msgs::Marker::DELETE;
  arr->markers.push_back(proj);
  markers_pub_.publish(arr);
}

void TrackerRos::publishImage(const dvs_msgs::EventArray& msg)
{
  // Events of the packet (undistorted positions: ON white, OFF grey) and the tracked segments.
  const int w = static_cast<int>(tracker_->intrinsics().cx * 2 + 1), h = static_cast<int>(tracker_->intrinsics().cy * 2 + 1);
  cv::Mat img(std::max(h, 1), std::max(w, 1), CV_8UC3, cv::Scalar(0, 0, 0));
  for (const auto& e : msg.events)
    if (e.x < img.cols && e.y < img.rows)
      img.at<cv::Vec3b>(e.y, e.x) = e.polarity ? cv::Vec3b(255, 255, 255) : cv::Vec3b(128, 128, 128);
  if (tracker_->state() == TrackerState::kTracking)
    for (const auto& s : tracker_->projectedSegments())
      cv::line(img, cv::Point2d(s.a.x(), s.a.y()), cv::Point2d(s.b.x(), s.b.y()), cv::Scalar(0, 0, 255), 1,
               cv::LINE_AA);
  std_msgs::Header header;
  header.stamp = msg.events.empty() ? msg.header.stamp : msg.events.back().ts;
  header.frame_id = settings_.camera_frame;
  image_pub_.publish(cv_bridge::CvImage(header, "bgr8", img).toImageMsg());
}

void TrackerRos::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat)
{
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  const double dt = std::max(1e-6, (ros::WallTime::now() - last_diag_).toSec());
  last_diag_ = ros::WallTime::now();
  if (!tracker_)
  {
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "waiting for the camera calibration");
    return;
  }
  const TrackerState s = tracker_->state();
  stat.summary(s == TrackerState::kTracking ? diagnostic_msgs::DiagnosticStatus::OK
                                            : diagnostic_msgs::DiagnosticStatus::WARN,
               toString(s));
  const auto& st = tracker_->stats();
  stat.add("state", toString(s));
  stat.add("event rate [ev/s]", events_since_diag_ / dt);
  stat.add("pose update rate [1/s]", updates_since_diag_ / dt);
  stat.add("events", st.events);
  stat.add("events attributed", st.events_attributed);
  stat.add("pose updates", st.pose_updates);
  stat.add("initializations", st.initializations);
  stat.add("re-initializations", st.reinitializations);
  stat.add("losses", st.losses);
  stat.add("last loss reason", tracker_->lastLossReason());
  stat.add("events outside the sensor", st.events_outside_sensor);
  stat.add("restarts after time went back", st.time_jumps);
  stat.add("gaps bridged by the IMU", st.gaps_bridged);
  // A corner only in view: the track is held without a pose for up to partial_view_grace_s.
  stat.add("partial view held now (no pose)", tracker_->partialViewHeld() ? "yes" : "no");
  stat.add("partial views held / resumed", std::to_string(st.partial_views_held) + " / " +
                                               std::to_string(st.partial_views_resumed));
  stat.add("partial views: time held [s]", st.partial_view_held_s);
  if (tracker_->partialViewHeld())
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, std::string(toString(s)) + kPartialViewHeldNote);
  // While there is no pose, say why (the stage that stops the detections), not only the state.
  const InitializerStats& is = tracker_->initializerStats();
  stat.add("initialiser: events voted / offered", std::to_string(is.events_voted) + " / " + std::to_string(is.events));
  stat.add("initialiser: detection attempts", is.attempts);
  stat.add("initialiser: counters", is.json());
  if (s != TrackerState::kTracking)
  {
    const std::string why = is.noPoseReason();
    stat.add("initialiser: why no pose", why);
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, std::string(toString(s)) + ": " + why);
  }
  if (st.events_outside_sensor > 0 || st.time_jumps > 0)
    stat.mergeSummary(diagnostic_msgs::DiagnosticStatus::WARN, "input problems (see the counters)");
  // Overload: what the tracker left out to keep up (never silent).
  std::unique_lock<std::mutex> q(queue_mutex_);
  const OverloadStats& o = overload_.stats();
  stat.add("queued events", pending_events_);
  stat.add("longest queue wait [ms]", queue_wait_max_s_ * 1e3);
  stat.add("tracking cost [us/event]", overload_.secondsPerEvent() * 1e6);
  stat.add("initialisation cost [us/event]", overload_.secondsPerEventInitialising() * 1e6);
  stat.add("overload: stride now (1: every event tracked)", o.last_stride);
  stat.add("overload: events skipped", o.events_skipped);
  stat.add("overload: packets tracked with a stride", o.packets_strided);
  stat.add("overload: packets skipped whole while initialising", o.packets_skipped);
  stat.add("overload: events in packets skipped whole", o.events_skipped_whole);
  stat.add("overload: packets dropped (max_queued_events)", o.packets_dropped);
  stat.add("overload: events dropped", o.events_dropped);
  if (o.events_skipped > skipped_at_diag_ || o.events_dropped > dropped_at_diag_)
    stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                 stat.message + "; falling behind: events skipped or dropped to keep the latency (see overload:)");
  skipped_at_diag_ = o.events_skipped;
  dropped_at_diag_ = o.events_dropped;
  queue_wait_max_s_ = 0;
  q.unlock();
  // Event -> pose published, per event, since the start (latency_split.h); "no samples" for the
  // total when the clock is not the events' (a replay without use_sim_time).
  stat.add("latency: total, event -> pose published", latency_.total().summaryMs());
  stat.add("latency: accumulation, event -> last event of its packet", latency_.accumulation().summaryMs());
  stat.add("latency: transport, last event -> packet arrived", latency_.transport().summaryMs());
  stat.add("latency: queue, arrived -> taken by the tracking thread", latency_.queue().summaryMs());
  stat.add("latency: processing", latency_.processing().summaryMs());
  stat.add("latency: publishing", latency_.publishing().summaryMs());
  stat.add("latency: packets with the clock away from the events' time", latency_.clockMismatches());
  stat.add("IMU messages", imu_messages_);
  if (imu_)
  {
    const auto& is = imu_->stats();
    stat.add("IMU status", toString(imu_->status()));
    stat.add("IMU message", imu_->statusMessage());
    stat.add("IMU samples absurd", is.samples_absurd);
    stat.add("IMU samples out of order", is.samples_out_of_order);
    stat.add("IMU fallbacks to vision", is.fallbacks);
    const auto& f = imu_->filter();
    char buf[160];
    std::snprintf(buf, sizeof buf, "%.5f %.5f %.5f", f.gyroBias().x(), f.gyroBias().y(), f.gyroBias().z());
    stat.add("IMU gyro bias [rad/s]", buf);
    std::snprintf(buf, sizeof buf, "%.4f %.4f %.4f", f.accelBias().x(), f.accelBias().y(), f.accelBias().z());
    stat.add("IMU accel bias [m/s^2]", buf);
    std::snprintf(buf, sizeof buf, "%.3f %.3f %.3f", f.gravity().x(), f.gravity().y(), f.gravity().z());
    stat.add("gravity in the world [m/s^2]", buf);
    // An IMU stream that is there but not used is a fault the operator must see.
    if (imu_messages_ > 0 && isSetAside(imu_->status()))
      stat.mergeSummary(diagnostic_msgs::DiagnosticStatus::WARN, std::string("IMU not used: ") + imu_->statusMessage());
    else if (imu_->gravityRejected())
      stat.mergeSummary(diagnostic_msgs::DiagnosticStatus::WARN, std::string("IMU partly used: ") + imu_->statusMessage());
  }
  events_since_diag_ = updates_since_diag_ = 0;
}
}  // namespace dvs_line_tracker
