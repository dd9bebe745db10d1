// Offline tracking: events (events.txt, a bag or AEDAT) + calibration + map in, TUM trajectory
// out (one line per pose update, T_world_camera), and a one-line JSON summary on stdout.
//
//   track_offline --events events.txt --calib calib.txt --map map.yaml --out trajectory.txt
//   track_offline --bag in.bag [--topic /dvs/events] --camera-info cam.yaml --map map.yaml --out traj.txt
#include <dvs_calibration/camera_model.h>
#include <dvs_calibration/trajectory_file.h>
#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/checked_write.h>
#include <dvs_driver/command_line.h>
#include <dvs_driver/recording.h>
#include <dvs_driver/event_validation.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/event_text_io.h>
#include <dvs_driver/imu_text_io.h>
#include <dvs_driver/progress_meter.h>
#include <dvs_line_tracker/imu_propagator.h>
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_line_tracker/tracker_params.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <sys/stat.h>

using namespace dvs_line_tracker;

namespace
{
void usage()
{
  std::cerr << "usage: track_offline (--events FILE | --bag FILE [--topic /dvs/events] | --aedat FILE)\n"
               "                     FILE: any recording (events.txt, AEDAT 2.0/3.1/4.0, Prophesee RAW, HDF5, bag),\n"
               "                     its format detected from its bytes\n"
               "                     (--calib calib.txt | --camera-info FILE.yaml | --preset dvs128)\n"
               "                     [--width 128 --height 128] [--map map.yaml] --out trajectory.txt\n"
               "                     [--params params.yaml] [--solver incremental|full] [--buffer-size N]\n"
               "                     [--imu imu.txt | --imu recording] [--odometry odometry.txt]\n"
               "--imu fuses an IMU (imu.txt: 't ax ay az gx gy gz', s, m/s^2, rad/s; 'recording': the samples the\n"
               "events' recording carries: AEDAT 2.0 DAVIS, AEDAT 4.0 IMUS, sensor_msgs/Imu beside the bag's events);\n"
               "--odometry writes the filter's estimate per IMU sample: 't tx ty tz qx qy qz qw vx vy vz' and the\n"
               "1-sigma of position (3) and orientation (3) (m, rad).\n"
               "Writes TUM lines 't tx ty tz qx qy qz qw' (T_world_camera) per pose update and prints a JSON\n"
               "summary. Without --map the thesis's 0.9 m square (plane z=0, up +y) is tracked.\n"
               "track_offline --list-params prints every parameter (name, default, unit, range, meaning).\n";
}

// Exact decimal seconds with nanosecond resolution.
std::string formatSeconds(int64_t t_ns)
{
  std::string s;
  dvs_calibration::appendSeconds(s, t_ns);
  return s;
}

struct Args
{
  std::map<std::string, std::string> kv;
  bool has(const std::string& k) const { return kv.count(k) > 0; }
  std::string get(const std::string& k, const std::string& def = "") const
  {
    auto it = kv.find(k);
    return it == kv.end() ? def : it->second;
  }
};

/// The events file named in the arguments (for messages).
std::string inputName(const Args& args)
{
  return args.has("events") ? args.get("events") : args.has("bag") ? args.get("bag") : args.get("aedat");
}

/// The input's size in bytes (0 when unknown), for the progress line.
uint64_t inputBytes(const Args& args)
{
  struct stat st;
  return ::stat(inputName(args).c_str(), &st) == 0 ? static_cast<uint64_t>(st.st_size) : 0;
}

/// One line of --odometry.
void appendOdometryLine(const ImuOdometry& o, std::string& out)
{
  const Eigen::Vector3d p = o.T_world_camera.p_world_camera();
  const Eigen::Quaterniond q = o.T_world_camera.q_world_camera();
  const auto& c = o.pose_covariance;
  char line[320];
  const int n = std::snprintf(
      line, sizeof(line), "%s %.6f %.6f %.6f %.7f %.7f %.7f %.7f %.5f %.5f %.5f %.3e %.3e %.3e %.3e %.3e %.3e\n",
      formatSeconds(o.t_ns).c_str(), p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w(), o.velocity_world.x(),
      o.velocity_world.y(), o.velocity_world.z(), std::sqrt(c(3, 3)), std::sqrt(c(4, 4)), std::sqrt(c(5, 5)),
      std::sqrt(c(0, 0)), std::sqrt(c(1, 1)), std::sqrt(c(2, 2)));
  out.append(line, static_cast<size_t>(std::min<int>(n, sizeof(line) - 1)));
}

/// The IMU fusion's counters and state for the JSON summary.
std::string imuJson(const ImuPropagator& p)
{
  const auto& s = p.stats();
  const auto& f = p.filter();
  char buf[640];
  std::snprintf(buf, sizeof(buf),
                "{\"status\": \"%s\", \"message\": \"%s\", \"samples\": %llu, \"samples_absurd\": %llu, "
                "\"samples_out_of_order\": %llu, \"updates\": %llu, \"updates_rejected\": %llu, \"fallbacks\": %llu, "
                "\"gyro_bias\": [%.5f, %.5f, %.5f], \"accel_bias\": [%.4f, %.4f, %.4f], \"gravity\": [%.4f, %.4f, %.4f]}",
                toString(p.status()), p.statusMessage().c_str(), static_cast<unsigned long long>(s.samples),
                static_cast<unsigned long long>(s.samples_absurd), static_cast<unsigned long long>(s.samples_out_of_order),
                static_cast<unsigned long long>(s.updates), static_cast<unsigned long long>(s.updates_rejected),
                static_cast<unsigned long long>(s.fallbacks), f.gyroBias().x(), f.gyroBias().y(), f.gyroBias().z(),
                f.accelBias().x(), f.accelBias().y(), f.accelBias().z(), f.gravity().x(), f.gravity().y(),
                f.gravity().z());
  return buf;
}

/// A whole number in [1, max] for option `name`, or an error naming the option and the value.
int parseSize(const std::string& text, const char* name, long max = dvs_calibration::kMaxSensorSide)
{
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno != 0 || v <= 0 || v > max)
    throw std::runtime_error(std::string(name) + " must be a whole number in [1, " + std::to_string(max) + "] (got '" +
                             text + "')");
  return static_cast<int>(v);
}
}  // namespace

int main(int argc, char** argv)
{
  Args args;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help")
    {
      usage();
      return 0;
    }
    if (a == "--list-params")
    {
      // The README's tables: the tracker's parameters (YAML --params and ROS ~name) and the node's.
      LineTrackerParams params;
      std::string solver = solverTypeName(params.estimator.solver);
      TrackerNodeSettings node;
      std::cout << trackerParamTable(params, solver).markdownTable() << "\n" << nodeParamTable(node).markdownTable();
      return 0;
    }
    if (a.rfind("--", 0) != 0 || i + 1 >= argc)
    {
      std::cerr << "track_offline: unexpected argument '" << a << "' (every option takes a value)\n";
      usage();
      return 2;
    }
    args.kv[a.substr(2)] = argv[++i];
  }
  static const char* known[] = {"events", "bag", "topic", "aedat", "calib", "camera-info", "preset", "width",
                                "height", "map", "out", "params", "solver", "buffer-size", "imu", "odometry"};
  for (const auto& [k, v] : args.kv)
    if (std::find(std::begin(known), std::end(known), k) == std::end(known))
    {
      std::cerr << "track_offline: unknown option --" << k << "\n";
      usage();
      return 2;
    }
  const int sources = args.has("events") + args.has("bag") + args.has("aedat");
  if (sources != 1 || !args.has("out"))
  {
    std::cerr << "track_offline: give exactly one of --events, --bag, --aedat, and --out\n";
    usage();
    return 2;
  }
  try
  {
    // Inputs (parsing is not part of the processing time).
    dvs_driver::EventStream stream;
    dvs_driver::EventChecks input_checks;
    dvs_driver::ImuVector recording_imu;
    {
      // Any recording, its format detected from its bytes (--bag and --aedat are the same option).
      dvs_driver::ProgressMeter meter("track_offline: reading " + inputName(args), 0);
      dvs_driver::Recording recording = dvs_driver::readRecording(
          inputName(args), args.get("topic", "/dvs/events"), meter.enabled() ? meter.callback() : dvs_driver::ReadProgress());
      meter.finish(recording.contents.stream.events.size(), inputBytes(args));
      std::cerr << "track_offline: " << inputName(args) << ": " << recording.format << ", "
                << recording.contents.stream.events.size() << " events"
                << (recording.contents.stream.width > 0
                        ? ", " + std::to_string(recording.contents.stream.width) + "x" +
                              std::to_string(recording.contents.stream.height)
                        : std::string(", no sensor size in the file"))
                << "\n";
      for (const std::string& w : recording.warnings)
        std::cerr << "track_offline: warning: " << inputName(args) << ": " << w << "\n";
      stream = std::move(recording.contents.stream);
      recording_imu = std::move(recording.contents.imu);
      input_checks = recording.contents.checks;  // what the reader repaired or skipped
    }

    // The sensor size: from the recording when it says, else --width/--height, else a
    // camera_info YAML; a calib.txt has none, so without any of these the DVS128's 128x128 is
    // assumed (and said). Events outside the size are counted and reported, never silent.
    int width = 0, height = 0;
    if (stream.width > 0 && stream.height > 0)
    {
      width = static_cast<int>(stream.width);
      height = static_cast<int>(stream.height);
    }
    if (args.has("width"))
      width = parseSize(args.get("width"), "--width");
    if (args.has("height"))
      height = parseSize(args.get("height"), "--height");
    dvs_calibration::CameraModel camera;
    bool size_assumed = false;
    if (args.has("calib") || args.has("camera-info"))
    {
      const std::string file = args.has("calib") ? args.get("calib") : args.get("camera-info");
      if (!dvs_calibration::isCameraInfoYamlPath(file) && (width <= 0 || height <= 0))
      {
        width = width > 0 ? width : 128;
        height = height > 0 ? height : 128;
        size_assumed = true;
        std::cerr << "track_offline: " << file << " and the events give no sensor size: assuming " << width << "x"
                  << height << " (DVS128; give --width/--height otherwise)\n";
      }
      camera = dvs_calibration::loadCameraFile(file, width, height);
    }
    else if (args.has("preset"))
      camera = dvs_calibration::CameraModel::preset(args.get("preset"));
    else
      throw std::runtime_error("give --calib, --camera-info or --preset");
    if (size_assumed)
    {
      // An assumed size must fit every event, or the recording is from another sensor: refuse it
      // rather than track part of it (an explicitly given size only counts and warns).
      for (size_t i = 0; i < stream.events.size(); ++i)
      {
        const dvs_driver::Event& e = stream.events[i];
        if (e.x >= camera.width() || e.y >= camera.height())
          throw std::runtime_error(inputName(args) + ": event " + std::to_string(i + 1) + " (t " +
                                   formatSeconds(e.t_ns) + " s, x " + std::to_string(e.x) + ", y " +
                                   std::to_string(e.y) + ") lies outside the assumed " + std::to_string(width) + "x" +
                                   std::to_string(height) + " sensor: give the sensor size with --width/--height "
                                   "(or a camera_info YAML)");
      }
    }

    // The one validation step of every input path: outside the sensor, backwards, duplicates.
    dvs_driver::EventValidator validator(static_cast<uint32_t>(camera.width()), static_cast<uint32_t>(camera.height()));
    validator.check(stream.events.data(), stream.events.data() + stream.events.size());
    input_checks.merge(validator.checks());
    if (!input_checks.clean())
      std::cerr << "track_offline: warning: " << inputName(args) << ": " << input_checks.summary() << "\n";
    if (stream.events.empty())
      std::cerr << "track_offline: warning: " << inputName(args) << " holds no events\n";

    const LineMap map = args.has("map") ? loadLineMap(args.get("map")) : defaultSquareMap();
    LineTrackerParams params;
    if (args.has("params"))
      loadTrackerParamsYaml(args.get("params"), params);
    if (args.has("solver") && !parseSolverType(args.get("solver"), params.estimator.solver))
      throw std::runtime_error("--solver must be 'incremental' or 'full'");
    if (args.has("buffer-size"))
      params.buffer_size = parseSize(args.get("buffer-size"), "--buffer-size", 1024);

    // Opened before tracking so that a bad output path fails at once (checked_write.h: every
    // write, the flush and the close are checked; the file appears complete or not at all).
    dvs_driver::CheckedFileWriter out(args.get("out"));

    // The IMU: a text file, or what the recording carries.
    dvs_driver::ImuVector imu;
    if (args.has("imu"))
    {
      if (args.get("imu") == "recording")
      {
        if (recording_imu.empty())
          throw std::runtime_error("--imu recording: " + inputName(args) + " carries no IMU samples");
        imu = std::move(recording_imu);
      }
      else
        imu = dvs_driver::readImuText(args.get("imu"));
      std::cerr << "track_offline: IMU: " << imu.size() << " samples"
                << (imu.empty() ? std::string()
                                : ", " + formatSeconds(imu.front().t_ns) + " to " + formatSeconds(imu.back().t_ns) + " s")
                << "\n";
    }
    else if (args.has("odometry"))
      throw std::runtime_error("--odometry needs --imu (the odometry is the IMU filter's estimate)");
    std::unique_ptr<dvs_driver::CheckedFileWriter> odometry_out;
    if (args.has("odometry"))
      odometry_out = std::make_unique<dvs_driver::CheckedFileWriter>(args.get("odometry"));

    LineTracker tracker(camera, map, params);
    std::shared_ptr<ImuPropagator> propagator;
    if (args.has("imu"))
    {
      propagator = std::make_shared<ImuPropagator>(params.imu);
      tracker.setPropagator(propagator);
    }
    size_t next_imu = 0;
    std::string odometry_text;
    struct Stamped
    {
      int64_t t_ns;
      Pose pose;
    };
    std::vector<Stamped> poses;
    poses.reserve(stream.events.size() + 1);
    // Progress on a terminal only (percent of the file = share of its events tracked).
    const uint64_t file_bytes = inputBytes(args), n_events = stream.events.size();
    dvs_driver::ProgressMeter progress("track_offline: tracking", file_bytes);
    const auto t0 = std::chrono::steady_clock::now();
    for (size_t i = 0; i < stream.events.size(); ++i)
    {
      const auto& e = stream.events[i];
      // Every IMU sample up to the event first (the sample in force at its time).
      while (propagator && next_imu < imu.size() && propagator->eventTimeOf(imu[next_imu]) <= e.t_ns)
      {
        const int64_t t_sample = propagator->eventTimeOf(imu[next_imu]);
        propagator->addSample(imu[next_imu++]);
        ImuOdometry o;
        if (odometry_out && propagator->odometry(t_sample, o))
          appendOdometryLine(o, odometry_text);
      }
      if (tracker.processEvent(e))
        poses.push_back({e.t_ns, tracker.pose()});
      if ((i & 0xFFF) == 0xFFF)
        progress.update(i + 1, file_bytes * (i + 1) / n_events);
    }
    progress.finish(n_events, file_bytes);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    out.write(std::string("# t tx ty tz qx qy qz qw (T_world_camera, TUM), dvs_line_tracker\n"));
    // Written in chunks of lines (std::to_chars; printf's format parsing was most of the
    // writing, a third of the tool's time on a long recording).
    std::string chunk;
    for (size_t i = 0; i < poses.size(); ++i)
    {
      const auto& s = poses[i];
      const Eigen::Vector3d p = s.pose.p_world_camera();
      const Eigen::Quaterniond q = s.pose.q_world_camera();
      dvs_calibration::appendSeconds(chunk, s.t_ns);
      for (const double v : {p.x(), p.y(), p.z()})
      {
        chunk += ' ';
        dvs_calibration::appendFixed(chunk, v, 6);
      }
      for (const double v : {q.x(), q.y(), q.z(), q.w()})
      {
        chunk += ' ';
        dvs_calibration::appendFixed(chunk, v, 7);
      }
      chunk += '\n';
      if (chunk.size() > (1u << 16) || i + 1 == poses.size())
      {
        out.write(chunk);
        chunk.clear();
      }
    }
    out.commit();
    if (odometry_out)
    {
      odometry_out->write(std::string("# t tx ty tz qx qy qz qw vx vy vz sigma_px sigma_py sigma_pz sigma_rx sigma_ry "
                                      "sigma_rz (T_world_camera, camera-centre velocity in the world; rotation sigmas "
                                      "in camera axes), dvs_line_tracker IMU filter\n"));
      odometry_out->write(odometry_text);
      odometry_out->commit();
    }

    const auto& st = tracker.stats();
    if (st.initializations == 0)
    {
      std::cerr << "track_offline: no pose: " << tracker.initializerStats().noPoseReason() << "\n";
    }
    if (st.events_outside_sensor > 0)
      std::cerr << "track_offline: warning: " << st.events_outside_sensor << " events lie outside the "
                << camera.width() << "x" << camera.height()
                << " sensor and were not used (wrong --width/--height or calibration?)\n";
    std::printf(
        "{\"events_read\": %zu, \"events_attributed\": %llu, \"pose_updates\": %llu, \"initializations\": %llu, "
        "\"reinitializations\": %llu, \"losses\": %llu, \"last_loss_reason\": %s, \"events_outside_sensor\": %llu, "
        "\"final_state\": \"%s\", "
        "\"processing_seconds\": %.6f, \"input\": {%s}, "
        "\"events_per_second\": %.0f, \"initializer\": %s, \"gaps_bridged\": %llu, "
        "\"partial_views_held\": %llu, \"partial_views_resumed\": %llu, \"partial_view_held_s\": %.4f, \"imu\": %s}\n",
        stream.events.size(), static_cast<unsigned long long>(st.events_attributed),
        static_cast<unsigned long long>(st.pose_updates), static_cast<unsigned long long>(st.initializations),
        static_cast<unsigned long long>(st.reinitializations), static_cast<unsigned long long>(st.losses),
        dvs_driver::jsonString(tracker.lastLossReason()).c_str(), static_cast<unsigned long long>(st.events_outside_sensor), toString(tracker.state()), seconds,
        input_checks.json().c_str(), seconds > 0 ? stream.events.size() / seconds : 0.0,
        tracker.initializerStats().json().c_str(), static_cast<unsigned long long>(st.gaps_bridged),
        static_cast<unsigned long long>(st.partial_views_held), static_cast<unsigned long long>(st.partial_views_resumed),
        st.partial_view_held_s, propagator ? imuJson(*propagator).c_str() : "null");
    return 0;
  }
  catch (const std::exception& e)
  {
    std::cerr << "track_offline: " << e.what() << "\n";
    return 1;
  }
}
