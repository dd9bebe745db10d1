// screen_loop: a real DVS filming the screen (thesis ch. 3). A node (not a nodelet: it owns the
// OpenGL window and its render loop on the main thread); the algorithms live in
// dvs_screen_sim_screen_loop (projection pipeline, alignment, timing), callbacks only queue events.
//
// 1. measures the refresh period (vsync'd swaps),
// 2. alignment: blinks the circle grid, detects it in dvs/events, computes the correction H
//    (retries up to ~alignment_attempts, refuses residuals above ~max_alignment_residual),
// 3. warns when the apparent motion exceeds one screen pixel per refresh (thesis 3.4.2),
// 4. plays the scenario's trajectory (slowed by ~time_scale), publishing the ground truth the
//    screen shows, stamped in the DVS's time base at the centre of each frame's display interval
//    (dvs/ground_truth/pose, /tf), and optionally
//    records a bag with the events and ground truth, time stamps rescaled to trajectory speed.
#include <dvs_driver/event_bag_io.h>
#include <dvs_msgs/EventArray.h>
#include <dvs_screen_sim/ros_conversions.h>
#include <dvs_screen_sim/screen_loop/gl_screen_renderer.h>
#include <dvs_screen_sim/screen_loop/grid_alignment.h>
#include <dvs_screen_sim/screen_loop/projection_pipeline.h>
#include <dvs_screen_sim/screen_loop/screen_timing.h>
#include <dvs_screen_sim/sim_config.h>
#include <rosbag/bag.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/transform_broadcaster.h>

#include <chrono>
#include <mutex>

using namespace dvs_screen_sim;
using namespace dvs_screen_sim::screen_loop;

namespace
{
int64_t hostNowNs()
{
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

/// Events from the DVS: counted into the alignment window and/or kept for the recording.
class EventSink
{
public:
  void callback(const dvs_msgs::EventArray::ConstPtr& msg)
  {
    const int64_t arrival = hostNowNs();
    std::lock_guard<std::mutex> lock(mutex_);
    if (!msg->events.empty())
      clock_.addPacket(dvs_driver::rosTimeToNs(msg->events.back().ts), arrival);
    if (width_ == 0 && msg->width > 0)
    {
      width_ = static_cast<int>(msg->width);
      height_ = static_cast<int>(msg->height);
    }
    if (collect_window_ && window_.width() > 0)
      for (const auto& e : msg->events)
        window_.add(dvs_driver::Event{dvs_driver::rosTimeToNs(e.ts), e.x, e.y, static_cast<bool>(e.polarity)});
    if (record_)
      dvs_driver::appendFromMessage(*msg, recorded_);
  }

  std::mutex mutex_;
  DvsClockOffset clock_;
  int width_ = 0, height_ = 0;
  bool collect_window_ = false;
  dvs_calibration::EventWindow window_;
  bool record_ = false;
  dvs_driver::EventVector recorded_;
};

template <typename T>
T param(ros::NodeHandle& pnh, const std::string& name, const T& def)
{
  T v;
  pnh.param(name, v, def);
  return v;
}

void require(bool ok, const std::string& what)
{
  if (!ok)
    throw std::invalid_argument(what);
}
}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "screen_loop");
  ros::NodeHandle nh, pnh("~");
  try
  {
    // ---- parameters (validated, each named in its error) ----
    const std::string scenario = param<std::string>(pnh, "scenario", "flip");
    const std::string config_file = param<std::string>(pnh, "config_file", "");
    const std::string calibration_file = param<std::string>(pnh, "calibration_file", "");
    const bool fullscreen = param(pnh, "fullscreen", true);
    const int width = param(pnh, "width", 1024), height = param(pnh, "height", 768);
    AlignmentPattern pattern;
    pattern.cols = param(pnh, "pattern_cols", 7);
    pattern.rows = param(pnh, "pattern_rows", 5);
    pattern.spacing_vp.x() = param(pnh, "pattern_spacing_x", 0.085);
    pattern.spacing_vp.y() = param(pnh, "pattern_spacing_y", 0.11);
    pattern.centre_vp.x() = param(pnh, "pattern_centre_x", 0.0);
    pattern.centre_vp.y() = param(pnh, "pattern_centre_y", 0.0);
    pattern.radius_px = param(pnh, "pattern_radius_px", 11.0);
    pattern.blink_frames = param(pnh, "blink_frames", 2);
    const double alignment_duration = param(pnh, "alignment_duration", 0.5);
    const int alignment_attempts = param(pnh, "alignment_attempts", 5);
    const double max_residual = param(pnh, "max_alignment_residual", 0.5);
    const std::string detector = param<std::string>(pnh, "detector", "counts");
    TimeScale time_scale{param(pnh, "time_scale", 1.0)};
    const std::string bag_path = param<std::string>(pnh, "bag", "");
    const std::string world_frame = param<std::string>(pnh, "world_frame", "world");
    const std::string gt_frame = param<std::string>(pnh, "ground_truth_frame", "dvs_gt");
    const int refresh_frames = param(pnh, "refresh_measurement_frames", 60);
    const double response_time = param(pnh, "monitor_response_time", 0.0);
    require(!fullscreen ? (width > 16 && height > 16) : true, "~width and ~height must be > 16");
    try
    {
      pattern.validate();
    }
    catch (const std::invalid_argument& e)
    {
      throw std::invalid_argument(std::string("~pattern_*: ") + e.what());
    }
    require(alignment_duration > 0.05, "~alignment_duration must be > 0.05 s");
    require(alignment_attempts >= 1, "~alignment_attempts must be >= 1");
    require(max_residual > 0, "~max_alignment_residual must be positive");
    require(refresh_frames >= 3, "~refresh_measurement_frames must be >= 3");
    require(response_time >= 0 && response_time < 0.1, "~monitor_response_time must be in [0, 0.1) s");
    try
    {
      time_scale.validate();
    }
    catch (const std::invalid_argument& e)
    {
      throw std::invalid_argument(std::string("~") + e.what());
    }
    GridAlignmentConfig detector_config;
    try
    {
      detector_config.detector = dvs_calibration::parseDetectorKind(detector);
    }
    catch (const std::invalid_argument& e)
    {
      throw std::invalid_argument(std::string("~detector: ") + e.what());
    }
    const SimConfig config = resolveSimConfigFile(scenario, config_file);
    const auto trajectory = makeTrajectory(config);

    EventSink sink;
    ros::Subscriber sub = nh.subscribe("dvs/events", 100, &EventSink::callback, &sink);
    ros::Publisher pose_pub = nh.advertise<geometry_msgs::PoseStamped>("dvs/ground_truth/pose", 100);
    tf2_ros::TransformBroadcaster tf;
    ros::AsyncSpinner spinner(1);
    spinner.start();

    // ---- the DVS's intrinsics ----
    dvs_calibration::CameraModel camera;
    if (!calibration_file.empty())
    {
      const bool yaml = calibration_file.size() > 5 &&
                        (calibration_file.substr(calibration_file.size() - 5) == ".yaml" ||
                         calibration_file.substr(calibration_file.size() - 4) == ".yml");
      camera = yaml ? dvs_calibration::loadCameraInfoYaml(calibration_file)
                    : dvs_calibration::loadCalibTxt(calibration_file, config.camera.width(), config.camera.height());
    }
    else
    {
      camera = config.camera;
      ROS_WARN("screen_loop: no ~calibration_file: using the configuration's camera (%dx%d, fx %.1f): calibrate the "
               "DVS first (dvs_calibration) for an accurate alignment",
               camera.width(), camera.height(), camera.intrinsics().fx);
    }
    ProjectionPipeline pipeline(camera);

    // ---- window, refresh period ----
    WindowConfig wc;
    wc.fullscreen = fullscreen;
    wc.width = width;
    wc.height = height;
    GlScreenRenderer gl(wc);
    RefreshPeriodEstimator refresh;
    for (int i = 0; i < refresh_frames && ros::ok(); ++i)
    {
      gl.clear(0.0);
      gl.swap();
      refresh.addSwapTime(hostNowNs() * 1e-9);
    }
    const double period = refresh.period();
    ROS_INFO("screen_loop: %dx%d window, refresh period %.2f ms%s", gl.width(), gl.height(), period * 1e3,
             gl.vsyncEnabled() ? "" : " (no vsync: this is the render time, not the screen's refresh)");

    // ---- alignment ----
    bool aligned = false;
    for (int attempt = 0; attempt < alignment_attempts && ros::ok() && !aligned; ++attempt)
    {
      {
        std::lock_guard<std::mutex> lock(sink.mutex_);
        sink.window_ = dvs_calibration::EventWindow(camera.width(), camera.height());
        sink.collect_window_ = false;
      }
      const auto t0 = std::chrono::steady_clock::now();
      for (int64_t frame = 0; ros::ok() && gl.pollEvents(); ++frame)
      {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (elapsed > alignment_duration + 0.1)
          break;
        {
          std::lock_guard<std::mutex> lock(sink.mutex_);
          sink.collect_window_ = elapsed > 0.1;  // the first 100 ms: the screen switching on
        }
        gl.clear(pattern.off_intensity);
        if ((frame / pattern.blink_frames) % 2 == 0)
          gl.drawViewportDiscs(patternCentresViewport(pattern), pattern.radius_px, pattern.on_intensity);
        gl.swap();
      }
      std::lock_guard<std::mutex> lock(sink.mutex_);
      sink.collect_window_ = false;
      const GridAlignment a = alignFromEvents(sink.window_, camera, pipeline, pattern, detector_config);
      if (!a.ok)
      {
        ROS_WARN("screen_loop: alignment attempt %d: %s (%zu events)", attempt + 1, a.reason.c_str(),
                 sink.window_.numEvents());
        continue;
      }
      ROS_INFO("screen_loop: alignment residual %.3f px rms, %.3f px max over %zu circles", a.result.residual_dvs_px.rms,
               a.result.residual_dvs_px.max, a.result.points);
      if (a.result.residual_dvs_px.rms > max_residual)
      {
        ROS_WARN("screen_loop: residual above ~max_alignment_residual (%.3f px): retrying", max_residual);
        continue;
      }
      pipeline.setCorrection(a.result.H);
      aligned = true;
    }
    if (!aligned)
    {
      ROS_ERROR("screen_loop: alignment failed after %d attempts: is the DVS looking at the screen, in focus, and "
                "does the grid lie inside its view (~pattern_*)?",
                alignment_attempts);
      return 1;
    }

    // ---- apparent motion ----
    const MotionCheck mc = checkApparentMotion(pipeline, *trajectory, motionSamplePoints(config.scene, {}), 0.0,
                                               config.duration, period > 0 ? period : 1.0 / 60, time_scale, gl.width(),
                                               gl.height());
    const std::string warn = motionWarning(mc);
    if (!warn.empty())
      ROS_WARN("screen_loop: %s", warn.c_str());

    // ---- playback ----
    PoseTrajectory groundtruth;
    {
      std::lock_guard<std::mutex> lock(sink.mutex_);
      sink.recorded_.clear();
      sink.record_ = !bag_path.empty();
      if (!sink.clock_.valid())
        ROS_WARN("screen_loop: no events received yet: ground truth stamped with the host clock");
    }
    const auto hold_ns = static_cast<int64_t>(std::llround((period > 0 ? period : 1.0 / 60) * 1e9));
    const int64_t start_host = hostNowNs();
    int64_t start_dvs = 0;
    {
      std::lock_guard<std::mutex> lock(sink.mutex_);
      start_dvs = sink.clock_.toDvsNs(start_host);
    }
    while (ros::ok() && gl.pollEvents())
    {
      const double t_traj = time_scale.trajectoryTime((hostNowNs() - start_host) * 1e-9);
      if (t_traj > config.duration)
        break;
      const Pose pose = trajectory->poseAt(t_traj);
      gl.clear(config.scene.background_reflectance);
      gl.setMatrices(pipeline.correctedProjection(), viewMatrix(pose));
      gl.drawScenePolygons(config.scene, t_traj);
      gl.swap();
      int64_t shown_dvs;
      {
        std::lock_guard<std::mutex> lock(sink.mutex_);
        shown_dvs = sink.clock_.toDvsNs(hostNowNs());
      }
      // The frame stays on the screen for one refresh from shown_dvs. The DVS's events of a frame
      // switch fill the band swept between two consecutive displayed poses, so each displayed
      // pose is stamped at the centre of its display interval (as emulate_screen_loop does).
      // The DVS sees it once the monitor's light has moved half-way (half its response time).
      shown_dvs += hold_ns / 2 + static_cast<int64_t>(std::llround(0.5 * response_time * 1e9));
      const StampedPose live{shown_dvs * 1e-9, pose};
      pose_pub.publish(toPoseStamped(live, world_frame));
      tf.sendTransform(toTransform(live, world_frame, gt_frame));
      // Recorded in the rescaled time base of the recorded events.
      groundtruth.push_back({(start_dvs + time_scale.rescaleStampNs(shown_dvs - start_dvs)) * 1e-9, pose});
    }

    // ---- recording: events and ground truth in trajectory time ----
    if (!bag_path.empty())
    {
      dvs_driver::EventVector events;
      {
        std::lock_guard<std::mutex> lock(sink.mutex_);
        sink.record_ = false;
        events.swap(sink.recorded_);
      }
      dvs_driver::EventVector rescaled;
      for (auto e : events)
        if (e.t_ns >= start_dvs)
        {
          e.t_ns = start_dvs + time_scale.rescaleStampNs(e.t_ns - start_dvs);
          rescaled.push_back(e);
        }
      rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
      dvs_driver::writeEventsBag(bag, "/dvs/events", rescaled, static_cast<uint32_t>(camera.width()),
                                 static_cast<uint32_t>(camera.height()));
      for (const auto& sp : groundtruth)
      {
        const auto msg = toPoseStamped(sp, world_frame);
        bag.write("/dvs/ground_truth/pose", msg.header.stamp, msg);
        tf2_msgs::TFMessage tfm;
        tfm.transforms.push_back(toTransform(sp, world_frame, gt_frame));
        bag.write("/tf", msg.header.stamp, tfm);
      }
      const auto info = dvs_calibration::toCameraInfoMsg(camera, "dvs");
      bag.write("/dvs/camera_info", secondsToRosTime(start_dvs * 1e-9), info);
      bag.close();
      ROS_INFO("screen_loop: recorded %zu events and %zu poses to %s", rescaled.size(), groundtruth.size(),
               bag_path.c_str());
    }
    ROS_INFO("screen_loop: playback finished");
  }
  catch (const std::exception& e)
  {
    ROS_FATAL("screen_loop: %s", e.what());
    return 1;
  }
  return 0;
}
