// Offline intrinsic calibration from a recording of the circle grid on a screen:
//   calibrate --events events.txt --grid 7x7 --spacing METRES --out camera.yaml
// Prints a one-line JSON summary on stdout; exit 0 = calibrated, 1 = could not calibrate,
// 2 = bad arguments or unreadable input.
#include <dvs_calibration/calibration_report.h>
#include <dvs_calibration/calibration_session.h>
#include <dvs_calibration/event_image.h>
#include <dvs_driver/aedat_reader.h>
#include <dvs_driver/event_bag_io.h>
#include <dvs_driver/recording.h>
#include <dvs_driver/event_text_io.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdlib>
#include <iostream>
#include <map>
#include <string>

namespace
{
const char* kUsage = R"(usage: calibrate (--events FILE | --bag FILE [--topic /dvs/events] | --aedat FILE) --grid CxR --spacing METRES --out camera.yaml
                 [--width W --height H] [options]
  --events FILE             any recording, its format detected from its bytes: events.txt (t x y p),
                            AEDAT 2.0/3.1/4.0, Prophesee RAW EVT 2.0/3.0, HDF5, a dvs_msgs bag
  --bag FILE                rosbag with dvs_msgs/EventArray on --topic (default /dvs/events)
  --aedat FILE              jAER AEDAT 2.0 recording (DVS128, DAVIS240/346)
  --grid CxR                circles: columns x rows (default 7x7)
  --spacing METRES          centre-to-centre distance of neighbouring circles (required)
  --out FILE                camera_info YAML to write (required)
  --width W --height H      sensor size (default 128x128, or the bag's / AEDAT file's size)
  --camera-name NAME        camera_name in the YAML (default dvs)
  --window-ms MS            integration window (default 75)
  --detector counts|blink   counts = threshold + closing (default); blink = ON/OFF alternation
  --count-threshold N       events per pixel for a white pixel (default 0 = automatic)
  --min-view-difference PX  keep a view when its corners moved this far from every kept view (default 8)
  --max-motion PX           a view must be still between two windows (default 0.5)
  --estimate-k3             also estimate k3 (default: fixed at 0)
  --undistorted-image FILE  write a PNG: the last kept view's events, raw (left) and undistorted (right)
  --verbose                 print every window's result (events, threshold, found, reason) to stderr
  --debug-images DIR        write every window's counts and pattern image as PNG into DIR
)";

struct Args
{
  std::map<std::string, std::string> values;
  bool has(const std::string& k) const { return values.count(k) > 0; }
  std::string get(const std::string& k, const std::string& def = "") const
  {
    auto it = values.find(k);
    return it == values.end() ? def : it->second;
  }
};

double parseDouble(const std::string& name, const std::string& text)
{
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0')
    throw std::invalid_argument("--" + name + " '" + text + "' is not a number");
  return v;
}

int parseInt(const std::string& name, const std::string& text)
{
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || v < -1000000000L || v > 1000000000L)
    throw std::invalid_argument("--" + name + " '" + text + "' is not an integer");
  return static_cast<int>(v);
}
}  // namespace

int main(int argc, char** argv)
{
  using namespace dvs_calibration;
  Args args;
  const std::map<std::string, bool> known = {
    {"events", true}, {"bag", true}, {"aedat", true}, {"topic", true}, {"grid", true}, {"spacing", true}, {"out", true},
    {"width", true}, {"height", true}, {"camera-name", true}, {"window-ms", true}, {"detector", true},
    {"count-threshold", true}, {"min-view-difference", true}, {"max-motion", true}, {"estimate-k3", false},
    {"undistorted-image", true}, {"verbose", false}, {"debug-images", true}, {"help", false}};
  for (int i = 1; i < argc; ++i)
  {
    std::string a = argv[i];
    if (a.rfind("--", 0) != 0 || !known.count(a.substr(2)))
    {
      std::cerr << "calibrate: unknown argument '" << a << "'\n" << kUsage;
      return 2;
    }
    a = a.substr(2);
    if (known.at(a))
    {
      if (i + 1 >= argc)
      {
        std::cerr << "calibrate: --" << a << " needs a value\n";
        return 2;
      }
      args.values[a] = argv[++i];
    }
    else
      args.values[a] = "1";
  }
  if (args.has("help"))
  {
    std::cout << kUsage;
    return 0;
  }

  SessionConfig config;
  std::string out_path;
  dvs_driver::EventStream stream;
  try
  {
    if (int(args.has("events")) + int(args.has("bag")) + int(args.has("aedat")) != 1)
      throw std::invalid_argument("give exactly one of --events FILE, --bag FILE or --aedat FILE");
    if (!args.has("spacing"))
      throw std::invalid_argument("--spacing METRES is required (centre-to-centre distance of the circles)");
    if (!args.has("out"))
      throw std::invalid_argument("--out FILE is required");
    out_path = args.get("out");
    config.grid.grid = parseGridSize(args.get("grid", "7x7"));
    config.calibrator.spacing_m = parseDouble("spacing", args.get("spacing"));
    if (!(config.calibrator.spacing_m > 0) || config.calibrator.spacing_m > 10)
      throw std::invalid_argument("--spacing must be a distance in metres in (0, 10], got " + args.get("spacing"));
    config.window_ns = static_cast<int64_t>(parseDouble("window-ms", args.get("window-ms", "75")) * 1e6);
    config.detector = parseDetectorKind(args.get("detector", "counts"));
    config.threshold.count_threshold = parseInt("count-threshold", args.get("count-threshold", "0"));
    config.views.min_view_difference_px = parseDouble("min-view-difference", args.get("min-view-difference", "8"));
    config.max_motion_px = parseDouble("max-motion", args.get("max-motion", "0.5"));
    config.calibrator.estimate_k3 = args.has("estimate-k3");

    // Any recording, its format detected from its bytes (--bag and --aedat are the same option).
    const std::string input = args.has("events") ? args.get("events") : args.has("bag") ? args.get("bag") : args.get("aedat");
    {
      dvs_driver::Recording recording = dvs_driver::readRecording(input, args.get("topic", dvs_driver::kDefaultEventTopic));
      const dvs_driver::EventStream& s = recording.contents.stream;
      std::cerr << "calibrate: " << input << ": " << recording.format << ", "
                << (s.width > 0 ? std::to_string(s.width) + "x" + std::to_string(s.height)
                                : std::string("no sensor size in the file"))
                << ", " << s.events.size() << " events\n";
      for (const std::string& w : recording.warnings)
        std::cerr << "calibrate: warning: " << input << ": " << w << "\n";
      stream = std::move(recording.contents.stream);
    }
    const bool size_assumed = stream.width == 0 && !args.has("width");
    config.width = stream.width > 0 ? static_cast<int>(stream.width) : 128;
    config.height = stream.height > 0 ? static_cast<int>(stream.height) : 128;
    if (args.has("width"))
      config.width = parseInt("width", args.get("width"));
    if (args.has("height"))
      config.height = parseInt("height", args.get("height"));
    validate(config);
    for (size_t i = 0; i < stream.events.size(); ++i)
    {
      const dvs_driver::Event& e = stream.events[i];
      if (e.x >= config.width || e.y >= config.height)
        throw std::invalid_argument(input + ": event " + std::to_string(i + 1) + " (t " + std::to_string(e.t_ns * 1e-9) +
                                    " s, x " + std::to_string(e.x) + ", y " + std::to_string(e.y) + ") lies outside the " +
                                    (size_assumed ? "assumed " : "") + std::to_string(config.width) + "x" +
                                    std::to_string(config.height) + " sensor: pass the sensor size with --width/--height");
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "calibrate: " << e.what() << "\n";
    return 2;
  }

  CalibrationSession session(config);
  cv::Mat last_view_counts;
  session.setWindowCallback([&](const WindowResult& w) {
    if (w.view_added)
      last_view_counts = w.counts.clone();
    if (args.has("verbose"))
      std::cerr << "window " << w.t_begin_ns * 1e-9 << " s: " << w.num_events << " events, threshold " << w.threshold
                << ", focus " << w.focus_score << (w.detection.found ? ", grid found" : ", no grid: ")
                << w.detection.reason << (w.stable ? ", stable" : "") << (w.view_added ? ", view kept" : "") << "\n";
    if (args.has("debug-images"))
    {
      cv::Mat a = countsToImage(w.counts), both;
      cv::hconcat(a, w.binary, both);
      cv::resize(both, both, cv::Size(), 4, 4, cv::INTER_NEAREST);
      writeImageChecked(args.get("debug-images") + "/window_" + std::to_string(w.t_begin_ns / 1000000) + ".png", both);
    }
  });
  try
  {
    session.addEvents(stream.events);
    session.flush();
  }
  catch (const std::exception& e)  // e.g. a debug image that cannot be written
  {
    std::cerr << "calibrate: " << e.what() << "\n";
    return 1;
  }

  CalibrationSummary summary;
  summary.windows = session.windowsProcessed();
  summary.detections = session.detections();
  summary.views_collected = session.views().size();
  CalibrationResult result;
  try
  {
    result = session.calibrate();
    summary.result = &result;
    saveCameraInfoYaml(out_path, result.camera, args.get("camera-name", "dvs"));
    summary.output_path = out_path;
    if (args.has("undistorted-image") && !last_view_counts.empty())
    {
      cv::Mat raw = countsToImage(last_view_counts);
      cv::Mat und = countsToImage(undistortCounts(last_view_counts, result.camera));
      cv::Mat both;
      cv::hconcat(raw, und, both);
      cv::resize(both, both, cv::Size(), 4, 4, cv::INTER_NEAREST);
      writeImageChecked(args.get("undistorted-image"), both);
    }
  }
  catch (const std::exception& e)
  {
    summary.error = e.what();
    std::cout << toJson(summary) << std::endl;
    std::cerr << "calibrate: " << e.what() << "\n";
    return 1;
  }
  std::cout << toJson(summary) << std::endl;
  return 0;
}
