#include "driver_nodelet.h"

#include <dvs_driver/device_input.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_file.h>
#include <dvs_driver/file_input.h>

#include <pluginlib/class_list_macros.hpp>
#include <ros/package.h>

namespace dvs_driver
{
namespace
{
int64_t nowNs()
{
  return rosTimeToNs(ros::Time::now());
}

[[noreturn]] void badParameter(const std::string& name, const std::string& why)
{
  ROS_FATAL_STREAM("dvs_driver: parameter ~" << name << ": " << why);
  throw std::invalid_argument("dvs_driver: parameter ~" + name + ": " + why);
}
}  // namespace

DriverNodelet::~DriverNodelet()
{
  if (input_)
    input_->stop();  // joins the input thread before members go away
}

void DriverNodelet::readParameters(ros::NodeHandle& pnh)
{
  pnh.param<std::string>("file", file_, "");
  pnh.param<std::string>("serial_number", serial_, "");
  pnh.param<std::string>("bias_preset", bias_preset_, "fast");
  pnh.param<std::string>("frame_id", frame_id_, "dvs");
  pnh.param<std::string>("camera_name", camera_name_, "");
  pnh.param<std::string>("camera_info_url", camera_info_url_, "");
  pnh.param<std::string>("file_time", file_time_, "replay");
  pnh.param("replay_speed", replay_speed_, 1.0);
  pnh.param("replay_loop", replay_loop_, false);
  pnh.param("wait_for_subscriber", wait_for_subscriber_, false);
  pnh.param("master", master_, true);
  pnh.param("reset_timestamps_delay", reset_timestamps_delay_, -1.0);
  pnh.param("camera_info_rate", camera_info_rate_, 30.0);
  pnh.param("reconnect_interval", reconnect_interval_, 0.5);
  pnh.param("transfers", transfers_, 8);
  pnh.param("transfer_size", transfer_size_, 4096);
  pnh.param("queue_size", queue_size_param_, -1);
  double period_ms;
  int max_events;
  pnh.param("packet_period_ms", period_ms, 1.0);
  pnh.param("max_events", max_events, 100000);

  if (!(period_ms > 0.0) || period_ms > 1000.0)
    badParameter("packet_period_ms", "must be in (0, 1000] ms, got " + std::to_string(period_ms));
  if (max_events < 1)
    badParameter("max_events", "must be >= 1, got " + std::to_string(max_events));
  if (replay_speed_ < 0.0)
    badParameter("replay_speed", "must be >= 0 (0 = as fast as possible), got " + std::to_string(replay_speed_));
  if (file_time_ != "replay" && file_time_ != "original")
    badParameter("file_time", "must be `replay` or `original`, got `" + file_time_ + "`");
  if (camera_info_rate_ < 0.0)
    badParameter("camera_info_rate", "must be >= 0 Hz, got " + std::to_string(camera_info_rate_));
  if (!(reconnect_interval_ > 0.0))
    badParameter("reconnect_interval", "must be > 0 s");
  if (transfers_ < 1 || transfers_ > 64)
    badParameter("transfers", "must be in [1, 64], got " + std::to_string(transfers_));
  if (transfer_size_ < 512 || transfer_size_ % 512 != 0)
    badParameter("transfer_size", "must be a multiple of 512 bytes, got " + std::to_string(transfer_size_));
  if (frame_id_.empty())
    badParameter("frame_id", "must not be empty");
  if (queue_size_param_ < -1)
    badParameter("queue_size", "must be -1 (automatic), 0 (unlimited) or a number of packets, got " +
                                   std::to_string(queue_size_param_));
  // Automatic: a recording played once cannot fill more than itself (already in memory), so a
  // slow subscriber gets every packet; a camera (or a looped recording) never ends, so what is
  // held for a subscriber that stalls is bounded to 1000 packets (1 s of 1 ms packets).
  if (queue_size_param_ >= 0)
    queue_size_ = static_cast<size_t>(queue_size_param_);
  else
    queue_size_ = (!file_.empty() && !replay_loop_) ? 0 : 1000;
  policy_.period_ns = static_cast<int64_t>(period_ms * 1e6 + 0.5);
  policy_.max_events = static_cast<size_t>(max_events);
}

void DriverNodelet::onInit()
{
  ros::NodeHandle pnh = getPrivateNodeHandle();
  ros::NodeHandle nh(getNodeHandle(), "dvs");
  readParameters(pnh);

  Dvs128Biases biases;
  try
  {
    const std::string dir = ros::package::getPath("dvs_driver") + "/config/biases";
    biases = loadBiasesYaml(biasPresetPath(dir, bias_preset_));
  }
  catch (const BiasError& e)
  {
    badParameter("bias_preset", e.what());
  }

  if (!file_.empty())
  {
    EventStream stream;
    std::string sensor;
    try
    {
      if (eventFileFormat(file_) == EventFileFormat::Bag)
        stream = readEventsBag(file_);
      else
      {
        EventFileContents c = readEventFile(file_);
        stream = std::move(c.stream);
        sensor = c.sensor_name;
        if (c.truncated_bytes)
          NODELET_WARN_STREAM("dvs_driver: " << file_ << " is truncated (" << c.truncated_bytes
                                             << " bytes of an incomplete last record ignored)");
      }
    }
    catch (const std::exception& e)
    {
      badParameter("file", e.what());
    }
    if (stream.width == 0 || stream.height == 0)
    {
      const std::string name = inferSensorSize(stream.events, stream.width, stream.height);
      if (sensor.empty())
        sensor = name;
    }
    width_ = stream.width;
    height_ = stream.height;
    if (camera_name_.empty())
      camera_name_ = (sensor.empty() ? std::string("dvs") : sensor) + "-file";
    if (file_time_ == "original")
    {
      if (!stream.events.empty() && stream.events.front().t_ns < 0)
        badParameter("file_time", "`original` needs non-negative times; " + file_ + " starts at " +
                                      std::to_string(stream.events.front().t_ns) + " ns (use `replay`)");
      stamps_.setBase(0);
    }
    else
    {
      replay_first_ns_ = stream.events.empty() ? 0 : stream.events.front().t_ns;
      stamps_.setBase(nowNs() - replay_first_ns_);
    }
    NODELET_INFO_STREAM("dvs_driver: replaying " << stream.events.size() << " events of " << file_ << " ("
                                                 << width_ << "x" << height_ << ") at "
                                                 << (replay_speed_ > 0 ? std::to_string(replay_speed_) + "x"
                                                                       : std::string("full speed")));
    FileInputOptions fo;
    fo.speed = replay_speed_;
    fo.loop = replay_loop_;
    fo.chunk_period_ns = std::min<int64_t>(policy_.period_ns, 100000);
    input_.reset(new FileInput(std::move(stream), file_, fo));
  }
  else
  {
    Dvs128DeviceOptions o;
    o.serial = serial_;
    o.master = master_;
    o.biases = biases;
    o.transfers = transfers_;
    o.transfer_size = transfer_size_;
    o.reconnect_interval_s = reconnect_interval_;
    try
    {
      device_input_ = new DeviceInput(o);
    }
    catch (const std::exception& e)
    {
      badParameter("transfers/transfer_size", e.what());
    }
    input_.reset(device_input_);
    auto_camera_name_ = camera_name_.empty();
    if (camera_name_.empty())
      camera_name_ = serial_.empty() ? "DVS128" : "DVS128-" + serial_;
    stamps_.setBase(nowNs());
  }

  // roscpp queues up to queue_size_ packets per subscriber connection not yet written to its
  // socket and silently discards the oldest beyond that (see ~queue_size).
  events_pub_ = nh.advertise<dvs_msgs::EventArray>("events", static_cast<uint32_t>(queue_size_));
  info_pub_ = nh.advertise<sensor_msgs::CameraInfo>("camera_info", 1);
  camera_nh_ = nh;
  cinfo_.reset(new camera_info_manager::CameraInfoManager(nh, camera_name_, camera_info_url_));
  if (device_input_)
  {
    if (master_)
      reset_pub_ = nh.advertise<std_msgs::Time>("reset_timestamps", 1, true);
    else
      reset_sub_ = nh.subscribe("reset_timestamps", 1, &DriverNodelet::resetTimestampsReceived, this);
    if (reset_timestamps_delay_ >= 0.0 && master_)
      reset_delay_timer_ = nh.createTimer(
          ros::Duration(std::max(reset_timestamps_delay_, 1e-3)),
          [this](const ros::TimerEvent&) {
            if (device_input_)
              device_input_->device().resetTimestamps();
          },
          true);
  }
  // A packet also goes out once it has waited one period of wall time, so sparse streams are
  // not held back until the next event.
  flush_timer_ = nh.createWallTimer(ros::WallDuration(std::max(policy_.period_ns * 1e-9, 0.0005)),
                                    [this](const ros::WallTimerEvent&) {
                                      std::lock_guard<std::mutex> lock(mutex_);
                                      if (packet_ && std::chrono::steady_clock::now() - packet_started_ >=
                                                         std::chrono::nanoseconds(policy_.period_ns))
                                        publishPacketLocked();
                                    });
  if (camera_info_rate_ > 0.0)
    info_timer_ = nh.createTimer(ros::Duration(1.0 / camera_info_rate_), &DriverNodelet::publishCameraInfo, this);

  diag_.reset(new diagnostic_updater::Updater(nh, pnh));
  diag_->setHardwareID(camera_name_);
  diag_->add("DVS event stream", this, &DriverNodelet::diagnose);
  last_diag_time_ = ros::WallTime::now();
  diag_timer_ = nh.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { diag_->update(); });

  // Biases and packet policy through dynamic_reconfigure. The server reads its start values from
  // the parameter server: a bias parameter (~diffOn, ...) set by the user wins, the others come
  // from the ~bias_preset file.
  for (size_t i = 0; i < kDvs128BiasCount; ++i)
    if (!pnh.hasParam(kDvs128BiasNames[i]))
      pnh.setParam(kDvs128BiasNames[i], static_cast<int>(biases.values[i]));
  reconfigure_server_.reset(new dynamic_reconfigure::Server<DvsDriverConfig>(reconfigure_mutex_, pnh));
  reconfigure_server_->setCallback(
      [this](DvsDriverConfig& config, uint32_t level) { reconfigure(config, level); });

  NODELET_INFO_STREAM("dvs_driver: starting " << input_->description() << ", packets of "
                                              << policy_.period_ns * 1e-6 << " ms or " << policy_.max_events
                                              << " events on " << events_pub_.getTopic());
  if (wait_for_subscriber_ && !device_input_)
  {
    // Replay only once someone listens (tests, offline pipelines): poll, do not block onInit.
    start_timer_ = nh.createWallTimer(ros::WallDuration(0.01), [this](const ros::WallTimerEvent&) {
      if (events_pub_.getNumSubscribers() > 0 && !started_)
      {
        started_ = true;
        start_timer_.stop();
        if (file_time_ == "replay")
        {
          // The first event is stamped with the time the replay starts, not the time it was loaded.
          std::lock_guard<std::mutex> lock(mutex_);
          stamps_.setBase(nowNs() - replay_first_ns_);
        }
        input_->start(*this);
      }
    });
    return;
  }
  started_ = true;
  input_->start(*this);  // returns at once; I/O runs on the input's thread
}

void DriverNodelet::reconfigure(DvsDriverConfig& config, uint32_t level)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    policy_.period_ns = static_cast<int64_t>(config.packet_period_ms * 1e6 + 0.5);
    policy_.max_events = static_cast<size_t>(config.max_events);
  }
  if (!device_input_)
    return;
  Dvs128Biases b;
  const int values[kDvs128BiasCount] = {config.cas,  config.injGnd, config.reqPd,  config.puX,
                                        config.diffOff, config.req, config.refr,   config.puY,
                                        config.diffOn, config.diff, config.foll, config.Pr};
  for (size_t i = 0; i < kDvs128BiasCount; ++i)
    b.values[i] = static_cast<uint32_t>(values[i]);
  if (b != device_input_->device().biases() || level == 0xFFFFFFFFu)
    device_input_->device().setBiases(b);
}

void DriverNodelet::onEvents(const Event* begin, const Event* end)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (events_pub_.getNumSubscribers() == 0)
  {
    // Nothing is built without subscribers, but time keeps moving.
    for (const Event* e = begin; e != end; ++e)
      stamps_.map(e->t_ns);
    events_without_subscriber_ += static_cast<uint64_t>(end - begin);
    packet_.reset();
    return;
  }
  for (const Event* e = begin; e != end; ++e)
  {
    const int64_t s = stamps_.map(e->t_ns);
    if (!packet_)
    {
      packet_.reset(new dvs_msgs::EventArray);
      packet_->events.reserve(reserve_);
      packet_first_ns_ = s;
      packet_started_ = std::chrono::steady_clock::now();
    }
    packet_->events.emplace_back();
    dvs_msgs::Event& m = packet_->events.back();
    m.x = e->x;
    m.y = e->y;
    m.ts.sec = static_cast<uint32_t>(s / 1000000000LL);
    m.ts.nsec = static_cast<uint32_t>(s % 1000000000LL);
    m.polarity = e->polarity;
    if (policy_.full(packet_first_ns_, s, packet_->events.size()))
      publishPacketLocked();
  }
}

void DriverNodelet::publishPacketLocked()
{
  if (!packet_ || packet_->events.empty())
    return;
  packet_->header.stamp = packet_->events.back().ts;
  packet_->header.frame_id = frame_id_;
  packet_->width = width_;
  packet_->height = height_;
  reserve_ = std::max(reserve_, packet_->events.size());
  events_published_ += packet_->events.size();
  ++packets_published_;
  events_pub_.publish(dvs_msgs::EventArrayConstPtr(std::move(packet_)));
  packet_.reset();
}

void DriverNodelet::onTimestampResetRequest()
{
  const int64_t now = nowNs();
  std::lock_guard<std::mutex> lock(mutex_);
  pending_reset_ns_ = slave_reset_ns_ >= 0 ? slave_reset_ns_ : now;
  slave_reset_ns_ = -1;
  if (master_ && reset_pub_)
  {
    std_msgs::Time msg;
    msg.data.fromNSec(static_cast<uint64_t>(pending_reset_ns_));
    reset_pub_.publish(msg);
  }
}

void DriverNodelet::onTimestampReset()
{
  std::lock_guard<std::mutex> lock(mutex_);
  publishPacketLocked();  // events of the old time base go out first
  stamps_.setBase(pending_reset_ns_ >= 0 ? pending_reset_ns_ : nowNs());
  pending_reset_ns_ = -1;
}

void DriverNodelet::resetTimestampsReceived(const std_msgs::Time::ConstPtr& msg)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    slave_reset_ns_ = static_cast<int64_t>(msg->data.toNSec());
  }
  NODELET_INFO("dvs_driver: timestamp reset from the master");
  if (device_input_)
    device_input_->device().resetTimestamps();
}

void DriverNodelet::onStatus(bool connected, const std::string& message)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    connected_ = connected;
    status_message_ = message;
    if (!connected)
      publishPacketLocked();  // events received before an unplug still go out
  }
  if (connected && auto_camera_name_ && serial_.empty() && device_input_)
  {
    // First camera found: its calibration is the one named after its serial, DVS128-<serial>.
    // (camera_info_manager's setCameraName() rejects '-', so the manager is made anew.)
    const std::string serial = device_input_->device().info().serial;
    const std::string name = "DVS128-" + serial;
    std::lock_guard<std::mutex> lock(cinfo_mutex_);
    if (!serial.empty() && name != camera_name_)
    {
      camera_name_ = name;
      cinfo_.reset();
      cinfo_.reset(new camera_info_manager::CameraInfoManager(camera_nh_, camera_name_, camera_info_url_));
      NODELET_INFO_STREAM("dvs_driver: camera name " << camera_name_);
    }
  }
  if (connected)
    NODELET_INFO_STREAM("dvs_driver: " << message);
  else
    NODELET_ERROR_STREAM("dvs_driver: " << message);
}

void DriverNodelet::onWarning(const std::string& message)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++warnings_;
  }
  NODELET_WARN_STREAM_THROTTLE(1.0, "dvs_driver: " << message);
}

void DriverNodelet::onEndOfInput()
{
  std::lock_guard<std::mutex> lock(mutex_);
  publishPacketLocked();
  end_of_input_ = true;
  NODELET_INFO_STREAM("dvs_driver: end of " << file_ << ": " << events_published_ << " events in "
                                           << packets_published_ << " packets");
}

void DriverNodelet::publishCameraInfo(const ros::TimerEvent&)
{
  if (info_pub_.getNumSubscribers() == 0)
    return;
  sensor_msgs::CameraInfoPtr info;
  {
    std::lock_guard<std::mutex> lock(cinfo_mutex_);
    info.reset(new sensor_msgs::CameraInfo(cinfo_->getCameraInfo()));
  }
  info->header.stamp = ros::Time::now();
  info->header.frame_id = frame_id_;
  if (info->width == 0)
  {
    info->width = width_;
    info->height = height_;
  }
  info_pub_.publish(info);
}

void DriverNodelet::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat)
{
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const uint64_t total = events_published_ + events_without_subscriber_;
  const double dt = (now - last_diag_time_).toSec();
  const double rate = dt > 0 ? (total - last_diag_events_) / dt : 0.0;
  last_diag_events_ = total;
  last_diag_time_ = now;
  stat.add("source", input_ ? input_->description() : std::string("none"));
  stat.add("event rate [events/s]", rate);
  stat.add("events published", events_published_);
  stat.add("packets published", packets_published_);
  stat.add("events without subscriber", events_without_subscriber_);
  stat.add("queue size [packets per subscriber]", queue_size_ == 0 ? std::string("unlimited") : std::to_string(queue_size_));
  stat.add("stamps clamped (time went backwards)", stamps_.clamped());
  stat.add("warnings", warnings_);
  if (device_input_)
  {
    const DeviceInputStats s = device_input_->stats();
    stat.add("transfers", s.device.transfers);
    stat.add("transfer errors", s.device.transfer_errors);
    stat.add("disconnects", s.device.disconnects);
    stat.add("reconnects", s.device.reconnects);
    stat.add("bytes", s.device.bytes);
    stat.add("sync events", s.decoder.sync_events);
    stat.add("non-monotonic device times", s.decoder.non_monotonic);
    if (!connected_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "camera not connected: " + status_message_);
    else if (s.device.transfer_errors > 0)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, "streaming, with transfer errors");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "streaming");
  }
  else
    stat.summary(diagnostic_msgs::DiagnosticStatus::OK, end_of_input_ ? "end of file" : "replaying");
}
}  // namespace dvs_driver

PLUGINLIB_EXPORT_CLASS(dvs_driver::DriverNodelet, nodelet::Nodelet)
