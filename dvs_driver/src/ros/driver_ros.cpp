#include "driver_ros.h"

#include <dvs_driver/device_input.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/file_replay.h>
#include <dvs_driver/param_table_ros.h>

#include <ros/package.h>

#include <stdexcept>

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
  throw std::invalid_argument("dvs_driver: parameter ~" + name + ": " + why);
}
}  // namespace

// The packet under construction is a dvs_msgs::EventArray (PacketBuilder's sink).
struct DriverRos::MessageSink
{
  DriverRos& d;
  void begin()
  {
    d.packet_.reset(new dvs_msgs::EventArray);
    d.packet_->events.reserve(d.reserve_);
  }
  void append(const Event& e, int64_t s)
  {
    d.packet_->events.emplace_back();
    dvs_msgs::Event& m = d.packet_->events.back();
    m.x = e.x;
    m.y = e.y;
    m.ts.sec = static_cast<uint32_t>(s / 1000000000LL);
    m.ts.nsec = static_cast<uint32_t>(s % 1000000000LL);
    m.polarity = e.polarity;
  }
  void finish() { d.publishPacketLocked(); }
  void discard() { d.packet_.reset(); }
};

DriverRos::DriverRos(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh, "dvs"), pnh_(pnh)
{
  readParameters();
  if (!params_.file.empty())
    openFile();
  else
    openCamera();
  advertise();
  start();
}

DriverRos::~DriverRos()
{
  if (input_)
    input_->stop();  // joins the input threads before members go away
}

void DriverRos::readParameters()
{
  // Deprecated: ~packet_period_ms (milliseconds) for ~packet_period (seconds).
  if (pnh_.hasParam(kDeprecatedPacketPeriodMs))
  {
    double ms = 0;
    if (!pnh_.getParam(kDeprecatedPacketPeriodMs, ms))
      badParameter(kDeprecatedPacketPeriodMs, "must be a number (deprecated: use ~packet_period in seconds)");
    if (pnh_.hasParam("packet_period"))
      ROS_WARN_STREAM("dvs_driver: ~" << kDeprecatedPacketPeriodMs << " is deprecated and ignored: ~packet_period ("
                                      << "seconds) is set too");
    else
    {
      ROS_WARN_STREAM("dvs_driver: ~" << kDeprecatedPacketPeriodMs << " is deprecated: set ~packet_period: "
                                      << ms * 1e-3 << " (seconds) instead");
      params_.packet_period = ms * 1e-3;
    }
  }
  ParamTable table = driverParamTable(params_);
  loadRosParams(pnh_, table, driverAlsoKnownParams());  // throws naming the parameter
  queue_size_ = params_.publisherQueueSize();
  builder_.policy.period_ns = params_.packetPeriodNs();
  builder_.policy.max_events = static_cast<size_t>(params_.max_events);
  try
  {
    const std::string dir = ros::package::getPath("dvs_driver") + "/config/biases";
    biases_ = loadBiasesYaml(biasPresetPath(dir, params_.bias_preset));
  }
  catch (const BiasError& e)
  {
    badParameter("bias_preset", e.what());
  }
}

void DriverRos::openFile()
{
  std::unique_ptr<EventSource> source;
  std::string sensor;
  SourceProbe probe;
  try
  {
    source = openEventSource(params_.file);
    probe = probeSource(*source, width_, height_, sensor);
  }
  catch (const std::exception& e)
  {
    badParameter("file", e.what());
  }
  if (source->info().truncated_bytes)
    ROS_WARN_STREAM("dvs_driver: " << params_.file << " is truncated (" << source->info().truncated_bytes
                                   << " bytes of an incomplete last record ignored)");
  camera_name_ = params_.camera_name.empty() ? (sensor.empty() ? std::string("dvs") : sensor) + "-file"
                                             : params_.camera_name;
  if (params_.file_time == "original")
  {
    if (!probe.empty && probe.first_t_ns < 0)
      badParameter("file_time", "`original` needs non-negative times; " + params_.file + " starts at " +
                                    std::to_string(probe.first_t_ns) + " ns (use `replay`)");
    builder_.stamps.setBase(0);
  }
  else
  {
    replay_first_ns_ = probe.empty ? 0 : probe.first_t_ns;
    builder_.stamps.setBase(nowNs() - replay_first_ns_);
  }
  // What was detected: format, sensor size, the events when the file announces them (the count
  // read is logged at the end of the file).
  const EventSourceInfo& info = source->info();
  file_format_ = info.format.empty() ? "?" : info.format;
  ROS_INFO_STREAM("dvs_driver: replaying " << params_.file << ": " << file_format_ << ", "
                                           << width_ << "x" << height_
                                           << (info.width == 0 || info.height == 0 ? " (from its events)" : "")
                                           << (info.expected_events >= 0
                                                   ? ", " + std::to_string(info.expected_events) + " events"
                                                   : std::string())
                                           << ", streamed at "
                                           << (params_.replay_speed > 0 ? std::to_string(params_.replay_speed) + "x"
                                                                        : std::string("full speed")));
  FileReplayOptions fo;
  fo.speed = params_.replay_speed;
  fo.loop = params_.replay_loop;
  fo.chunk_period_ns = std::min<int64_t>(builder_.policy.period_ns, 100000);
  fo.queue_events = static_cast<size_t>(params_.replay_queue_events);
  fo.sensor_width = width_;  // events outside are dropped and counted (diagnostics)
  fo.sensor_height = height_;
  replay_ = new FileReplay(std::move(source), fo);
  input_.reset(replay_);
}

void DriverRos::openCamera()
{
  Dvs128DeviceOptions o;
  o.serial = params_.serial_number;
  o.master = params_.master;
  o.biases = biases_;
  o.transfers = params_.transfers;
  o.transfer_size = params_.transfer_size;
  o.reconnect_interval_s = params_.reconnect_interval;
  try
  {
    device_input_ = new DeviceInput(o);
  }
  catch (const std::exception& e)
  {
    badParameter("transfers/transfer_size", e.what());
  }
  input_.reset(device_input_);
  auto_camera_name_ = params_.camera_name.empty();
  camera_name_ = !params_.camera_name.empty() ? params_.camera_name
                 : params_.serial_number.empty() ? "DVS128"
                                                 : "DVS128-" + params_.serial_number;
  builder_.stamps.setBase(nowNs());
}

void DriverRos::advertise()
{
  // roscpp queues up to queue_size_ packets per subscriber connection not yet written to its
  // socket and silently discards the oldest beyond that (see ~queue_size).
  events_pub_ = nh_.advertise<dvs_msgs::EventArray>("events", static_cast<uint32_t>(queue_size_));
  info_pub_ = nh_.advertise<sensor_msgs::CameraInfo>("camera_info", 1);
  cinfo_.reset(new camera_info_manager::CameraInfoManager(nh_, camera_name_, params_.camera_info_url));
  if (device_input_)
  {
    if (params_.master)
      reset_pub_ = nh_.advertise<std_msgs::Time>("reset_timestamps", 1, true);
    else
      reset_sub_ = nh_.subscribe("reset_timestamps", 1, &DriverRos::resetTimestampsReceived, this);
    if (params_.reset_timestamps_delay >= 0.0 && params_.master)
      reset_delay_timer_ = nh_.createTimer(
          ros::Duration(std::max(params_.reset_timestamps_delay, 1e-3)),
          [this](const ros::TimerEvent&) {
            if (device_input_)
              device_input_->device().resetTimestamps();
          },
          true);
  }
  // A packet also goes out once it has waited one period of wall time, so sparse streams are
  // not held back until the next event.
  flush_timer_ = nh_.createWallTimer(ros::WallDuration(std::max(builder_.policy.period_ns * 1e-9, 0.0005)),
                                     [this](const ros::WallTimerEvent&) {
                                       std::lock_guard<std::mutex> lock(mutex_);
                                       MessageSink sink{*this};
                                       builder_.flushIfWaited(sink);
                                     });
  if (params_.camera_info_rate > 0.0)
    info_timer_ = nh_.createTimer(ros::Duration(1.0 / params_.camera_info_rate), &DriverRos::publishCameraInfo, this);

  diag_.reset(new diagnostic_updater::Updater(nh_, pnh_));
  diag_->setHardwareID(camera_name_);
  diag_->add("DVS event stream", this, &DriverRos::diagnose);
  last_diag_time_ = ros::WallTime::now();
  diag_timer_ = nh_.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { diag_->update(); });

  // Biases and packet policy through dynamic_reconfigure. The server reads its start values from
  // the parameter server: a bias parameter (~diffOn, ...) set by the user wins, the others come
  // from the ~bias_preset file; the packet policy is the validated one.
  for (size_t i = 0; i < kDvs128BiasCount; ++i)
    if (!pnh_.hasParam(kDvs128BiasNames[i]))
      pnh_.setParam(kDvs128BiasNames[i], static_cast<int>(biases_.values[i]));
  pnh_.setParam("packet_period", params_.packet_period);
  pnh_.setParam("max_events", params_.max_events);
  reconfigure_server_.reset(new dynamic_reconfigure::Server<DvsDriverConfig>(reconfigure_mutex_, pnh_));
  reconfigure_server_->setCallback(
      [this](DvsDriverConfig& config, uint32_t level) { reconfigure(config, level); });
}

void DriverRos::start()
{
  ROS_INFO_STREAM("dvs_driver: starting " << input_->description() << ", packets of "
                                          << builder_.policy.period_ns * 1e-9 << " s or "
                                          << builder_.policy.max_events << " events on " << events_pub_.getTopic());
  if (params_.wait_for_subscriber && !device_input_)
  {
    // Replay only once someone listens (tests, offline pipelines): poll, do not block.
    start_timer_ = nh_.createWallTimer(ros::WallDuration(0.01), [this](const ros::WallTimerEvent&) {
      if (events_pub_.getNumSubscribers() > 0 && !started_)
      {
        started_ = true;
        start_timer_.stop();
        if (params_.file_time == "replay")
        {
          // The first event is stamped with the time the replay starts, not the time it was opened.
          std::lock_guard<std::mutex> lock(mutex_);
          builder_.stamps.setBase(nowNs() - replay_first_ns_);
        }
        input_->start(*this);
      }
    });
    return;
  }
  started_ = true;
  input_->start(*this);  // returns at once; I/O runs on the input's threads
}

void DriverRos::reconfigure(DvsDriverConfig& config, uint32_t level)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    builder_.policy.period_ns = static_cast<int64_t>(config.packet_period * 1e9 + 0.5);
    builder_.policy.max_events = static_cast<size_t>(config.max_events);
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

void DriverRos::onEvents(const Event* begin, const Event* end)
{
  std::lock_guard<std::mutex> lock(mutex_);
  MessageSink sink{*this};
  if (events_pub_.getNumSubscribers() == 0)
  {
    // Nothing is built without subscribers, but time keeps moving.
    builder_.skip(begin, end, sink);
    events_without_subscriber_ += static_cast<uint64_t>(end - begin);
    return;
  }
  builder_.add(begin, end, sink);
}

void DriverRos::publishPacketLocked()
{
  if (!packet_ || packet_->events.empty())
    return;
  packet_->header.stamp = packet_->events.back().ts;
  packet_->header.frame_id = params_.frame_id;
  packet_->width = width_;
  packet_->height = height_;
  reserve_ = std::max(reserve_, packet_->events.size());
  events_published_ += packet_->events.size();
  ++packets_published_;
  events_pub_.publish(dvs_msgs::EventArrayConstPtr(std::move(packet_)));
  packet_.reset();
}

void DriverRos::onTimestampResetRequest()
{
  const int64_t now = nowNs();
  std::lock_guard<std::mutex> lock(mutex_);
  pending_reset_ns_ = slave_reset_ns_ >= 0 ? slave_reset_ns_ : now;
  slave_reset_ns_ = -1;
  if (params_.master && reset_pub_)
  {
    std_msgs::Time msg;
    msg.data.fromNSec(static_cast<uint64_t>(pending_reset_ns_));
    reset_pub_.publish(msg);
  }
}

void DriverRos::onTimestampReset()
{
  std::lock_guard<std::mutex> lock(mutex_);
  MessageSink sink{*this};
  builder_.flush(sink);  // events of the old time base go out first
  builder_.stamps.setBase(pending_reset_ns_ >= 0 ? pending_reset_ns_ : nowNs());
  pending_reset_ns_ = -1;
}

void DriverRos::resetTimestampsReceived(const std_msgs::Time::ConstPtr& msg)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    slave_reset_ns_ = static_cast<int64_t>(msg->data.toNSec());
  }
  ROS_INFO("dvs_driver: timestamp reset from the master");
  if (device_input_)
    device_input_->device().resetTimestamps();
}

void DriverRos::onStatus(bool connected, const std::string& message)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    connected_ = connected;
    status_message_ = message;
    if (!connected)
    {
      MessageSink sink{*this};
      builder_.flush(sink);  // events received before an unplug still go out
    }
  }
  if (connected && auto_camera_name_ && params_.serial_number.empty() && device_input_)
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
      cinfo_.reset(new camera_info_manager::CameraInfoManager(nh_, camera_name_, params_.camera_info_url));
      ROS_INFO_STREAM("dvs_driver: camera name " << camera_name_);
    }
  }
  if (connected)
    ROS_INFO_STREAM("dvs_driver: " << message);
  else
    ROS_ERROR_STREAM("dvs_driver: " << message);
}

void DriverRos::onWarning(const std::string& message)
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++warnings_;
  }
  ROS_WARN_STREAM_THROTTLE(1.0, "dvs_driver: " << message);
}

void DriverRos::onEndOfInput()
{
  std::lock_guard<std::mutex> lock(mutex_);
  MessageSink sink{*this};
  builder_.flush(sink);
  end_of_input_ = true;
  ROS_INFO_STREAM("dvs_driver: end of " << params_.file << " (" << file_format_ << ", " << width_ << "x" << height_
                                        << "): " << events_published_ + events_without_subscriber_ << " events read, "
                                        << events_published_ << " published in " << packets_published_ << " packets");
}

void DriverRos::onInputError(const std::string& message)
{
  std::lock_guard<std::mutex> lock(mutex_);
  MessageSink sink{*this};
  builder_.flush(sink);
  input_error_ = message;
  ROS_ERROR_STREAM("dvs_driver: replay stopped: " << message << " (" << events_published_
                                                  << " events published before)");
}

void DriverRos::publishCameraInfo(const ros::TimerEvent&)
{
  if (info_pub_.getNumSubscribers() == 0)
    return;
  sensor_msgs::CameraInfoPtr info;
  {
    std::lock_guard<std::mutex> lock(cinfo_mutex_);
    info.reset(new sensor_msgs::CameraInfo(cinfo_->getCameraInfo()));
  }
  info->header.stamp = ros::Time::now();
  info->header.frame_id = params_.frame_id;
  if (info->width == 0)
  {
    info->width = width_;
    info->height = height_;
  }
  info_pub_.publish(info);
}

void DriverRos::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat)
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
  stat.add("stamps clamped (time went backwards)", builder_.stamps.clamped());
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
    else if (s.decoder.non_monotonic > 0 || builder_.stamps.clamped() > 0)
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "streaming, with time stamps that went backwards (clamped: " +
                       std::to_string(s.decoder.non_monotonic) + " device times, " +
                       std::to_string(builder_.stamps.clamped()) + " stamps)");
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "streaming");
  }
  else
  {
    // The recording's validation (FileReplay::checks): WARN while anything was dropped,
    // repaired or is suspect.
    const EventChecks c = replay_ ? replay_->checks() : EventChecks();
    stat.add("events outside the sensor (dropped)", c.outside_sensor);
    stat.add("time stamps going backwards", c.backwards);
    stat.add("largest step back [s]", c.max_backwards_ns * 1e-9);
    stat.add("event times clamped (file)", c.clamped);
    stat.add("exact duplicate events", c.duplicates);
    const std::string state = end_of_input_ ? "end of file" : "replaying";
    if (!input_error_.empty())
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "replay stopped: " + input_error_);
    else if (!c.clean())
      stat.summary(diagnostic_msgs::DiagnosticStatus::WARN, state + ", input problems: " + c.summary());
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, state);
  }
}
}  // namespace dvs_driver
