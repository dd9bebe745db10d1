#include <dvs_screen_sim/sim_config.h>
#include <dvs_calibration/trajectory_file.h>

#include <algorithm>
#include <cmath>

namespace dvs_screen_sim
{
namespace
{
// Every parameter with its default. `~` (null) = "taken from the preset / file".
const char* kDefaultTree = R"YAML(
scenario: flip
seed: 0
duration: 0.0
time_offset: 0.0
groundtruth_rate: 1000.0
packet_period: 0.001
camera:
  preset: dvs128
  calibration_file: ""
  width: ~
  height: ~
  fx: ~
  fy: ~
  cx: ~
  cy: ~
  k1: ~
  k2: ~
  p1: ~
  p2: ~
  k3: ~
scene:
  file: ""
  background_reflectance: 0.9
  map_up: [0.0, 1.0, 0.0]
  polygons:
    - name: square
      reflectance: 0.1
      in_map: true
      vertices: [[-0.45, -0.45], [0.45, -0.45], [0.45, 0.45], [-0.45, 0.45]]
  images: []
trajectory:
  flip:
    distance: 2.0
    offset: [0.0, 0.0]
    peak_rate_deg_s: 1200.0
    rise: 0.5
    flips: 1
    first_flip_time: 0.75
    flip_interval: 1.5
    sway: 0.02
    sway_frequency: 0.8
  helix:
    start_distance: 1.0
    end_distance: 2.5
    tilt_deg: 30.0
    turns: 2.0
    duration: 4.0
  circle:
    distance: 1.0
    tilt_deg: 30.0
    turns: 2.0
    duration: 4.0
  linear:
    start_position: [-0.3, -0.2, 1.3]
    start_ypr_deg: [10.0, -5.0, -10.0]
    end_position: [0.3, 0.2, 1.8]
    end_ypr_deg: [-10.0, 5.0, 20.0]
    duration: 2.0
  random:
    distance: 1.5
    position_amplitude: [0.2, 0.2, 0.2]
    ypr_amplitude_deg: [10.0, 10.0, 30.0]
    min_frequency: 0.2
    max_frequency: 1.0
    components: 3
    duration: 5.0
  file:
    path: ""
events:
  threshold_on: 0.3
  threshold_off: 0.3
  min_threshold: 0.01
  log_eps: 0.001
  noise:
    preset: realistic
    threshold_sigma: ~
    refractory_period: ~
    latency: ~
    latency_jitter: ~
    background_rate: ~
    hot_pixel_fraction: ~
    hot_pixel_rate: ~
    random_initial_reference: ~
sampling:
  max_pixel_motion: 0.2
  min_dt: 1.0e-6
  max_dt: 1.0e-3
imu:
  rate: 1000.0
  gyro_noise_density: 1.7e-4
  gyro_random_walk: 2.0e-5
  accel_noise_density: 2.0e-3
  accel_random_walk: 3.0e-3
  initial_gyro_bias_max: 0.01
  initial_accel_bias_max: 0.05
  initial_gyro_bias: ~
  initial_accel_bias: ~
  gravity: [0.0, -9.81, 0.0]
  extrinsic_rotation: [0.0, 0.0, 0.0, 1.0]
  extrinsic_translation: [0.0, 0.0, 0.0]
)YAML";

void mergeInto(YAML::Node base, const YAML::Node& over, const std::string& path)
{
  if (!over.IsMap())
    throw ConfigError("configuration " + (path.empty() ? std::string("root") : "'" + path + "'") + " must be a map");
  for (const auto& kv : over)
  {
    const std::string key = kv.first.as<std::string>();
    const std::string full = path.empty() ? key : path + "." + key;
    if (!base[key])
      throw ConfigError("unknown configuration parameter '" + full + "'");
    YAML::Node b = base[key];
    if (b.IsMap() && kv.second.IsMap())
      mergeInto(b, kv.second, full);
    else if (b.IsMap())
      throw ConfigError("configuration parameter '" + full + "' must be a map");
    else
      base[key] = YAML::Clone(kv.second);
  }
}

template <typename T>
T as(const YAML::Node& node, const std::string& path)
{
  try
  {
    return node.as<T>();
  }
  catch (const YAML::Exception&)
  {
    throw ConfigError("configuration parameter '" + path + "' has the wrong type");
  }
}

double num(const YAML::Node& parent, const std::string& key, const std::string& path)
{
  const double v = as<double>(parent[key], path + "." + key);
  if (!std::isfinite(v))
    throw ConfigError("configuration parameter '" + path + "." + key + "' must be finite");
  return v;
}

Eigen::Vector3d vec3(const YAML::Node& parent, const std::string& key, const std::string& path)
{
  const auto v = as<std::vector<double>>(parent[key], path + "." + key);
  if (v.size() != 3)
    throw ConfigError("configuration parameter '" + path + "." + key + "' must have 3 numbers");
  return {v[0], v[1], v[2]};
}

YAML::Node flowSeq(std::initializer_list<double> values)
{
  YAML::Node n;
  n.SetStyle(YAML::EmitterStyle::Flow);
  for (double v : values)
    n.push_back(v);
  return n;
}

bool endsWith(const std::string& s, const std::string& suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

dvs_calibration::CameraModel resolveCamera(YAML::Node cam)
{
  const std::string preset = as<std::string>(cam["preset"], "camera.preset");
  const std::string file = as<std::string>(cam["calibration_file"], "camera.calibration_file");
  try
  {
    dvs_calibration::CameraModel model = dvs_calibration::CameraModel::preset(preset);
    dvs_calibration::CameraIntrinsics k = model.intrinsics();
    if (!cam["width"].IsNull())
      k.width = as<int>(cam["width"], "camera.width");
    if (!cam["height"].IsNull())
      k.height = as<int>(cam["height"], "camera.height");
    if (!file.empty())
    {
      if (endsWith(file, ".txt"))
        model = dvs_calibration::loadCalibTxt(file, k.width, k.height);
      else
        model = dvs_calibration::loadCameraInfoYaml(file);
      const int w = k.width, h = k.height;
      k = model.intrinsics();
      if (!cam["width"].IsNull())
        k.width = w;
      if (!cam["height"].IsNull())
        k.height = h;
    }
    double* fields[] = {&k.fx, &k.fy, &k.cx, &k.cy, &k.k1, &k.k2, &k.p1, &k.p2, &k.k3};
    const char* names[] = {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"};
    for (int i = 0; i < 9; ++i)
      if (!cam[names[i]].IsNull())
        *fields[i] = num(cam, names[i], "camera");
    model = dvs_calibration::CameraModel(k);
    cam["width"] = k.width;
    cam["height"] = k.height;
    for (int i = 0; i < 9; ++i)
      cam[names[i]] = *fields[i];
    return model;
  }
  catch (const dvs_calibration::CameraModelError& e)
  {
    throw ConfigError(std::string("camera: ") + e.what());
  }
}

NoiseConfig resolveNoise(YAML::Node n)
{
  const std::string preset = as<std::string>(n["preset"], "events.noise.preset");
  NoiseConfig cfg;
  try
  {
    cfg = noisePreset(preset);
  }
  catch (const std::invalid_argument& e)
  {
    throw ConfigError(std::string("events.noise.preset: ") + e.what());
  }
  struct Field
  {
    const char* name;
    double* value;
  } fields[] = {{"threshold_sigma", &cfg.threshold_sigma},   {"refractory_period", &cfg.refractory_period},
                {"latency", &cfg.latency},                   {"latency_jitter", &cfg.latency_jitter},
                {"background_rate", &cfg.background_rate},   {"hot_pixel_fraction", &cfg.hot_pixel_fraction},
                {"hot_pixel_rate", &cfg.hot_pixel_rate}};
  for (auto& f : fields)
  {
    if (!n[f.name].IsNull())
      *f.value = num(n, f.name, "events.noise");
    n[f.name] = *f.value;
  }
  if (!n["random_initial_reference"].IsNull())
    cfg.random_initial_reference = as<bool>(n["random_initial_reference"], "events.noise.random_initial_reference");
  n["random_initial_reference"] = cfg.random_initial_reference;
  return cfg;
}

ImuSimParams resolveImu(const YAML::Node& n)
{
  ImuSimParams imu;
  dvs_driver::ParamTable table = imuParamTable(imu);
  for (const auto& e : table.entries())
    *e.d = num(n, e.name, "imu");  // every scalar of the table is a double
  if (!n["initial_gyro_bias"].IsNull())
    imu.initial_gyro_bias = vec3(n, "initial_gyro_bias", "imu");
  if (!n["initial_accel_bias"].IsNull())
    imu.initial_accel_bias = vec3(n, "initial_accel_bias", "imu");
  imu.gravity = vec3(n, "gravity", "imu");
  imu.p_camera_imu = vec3(n, "extrinsic_translation", "imu");
  const auto q = as<std::vector<double>>(n["extrinsic_rotation"], "imu.extrinsic_rotation");
  if (q.size() != 4)
    throw ConfigError("configuration parameter 'imu.extrinsic_rotation' must have 4 numbers (qx, qy, qz, qw)");
  const Eigen::Quaterniond quat(q[3], q[0], q[1], q[2]);
  if (!(quat.norm() > 0.5 && quat.norm() < 2.0) || !quat.coeffs().allFinite())
    throw ConfigError("configuration parameter 'imu.extrinsic_rotation' must be a unit quaternion [qx, qy, qz, qw]");
  imu.q_camera_imu = quat.normalized();
  try
  {
    imu.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw ConfigError(e.what());
  }
  return imu;
}
}  // namespace

const std::vector<std::string>& scenarioNames()
{
  static const std::vector<std::string> names = {"flip", "helix", "circle", "linear", "random", "file"};
  return names;
}

YAML::Node defaultConfigTree(const std::string& scenario)
{
  YAML::Node tree = YAML::Load(kDefaultTree);
  tree["scenario"] = scenario;
  return tree;
}

std::unique_ptr<Trajectory> makeTrajectory(const SimConfig& config)
{
  const YAML::Node tr = config.resolved["trajectory"];
  const std::string& s = config.scenario;
  try
  {
    if (s == "flip")
    {
      const YAML::Node n = tr["flip"];
      const std::string p = "trajectory.flip";
      FlipTrajectoryParams f;
      f.distance = num(n, "distance", p);
      const auto off = as<std::vector<double>>(n["offset"], p + ".offset");
      if (off.size() != 2)
        throw ConfigError(p + ".offset must have 2 numbers");
      f.offset = Eigen::Vector2d(off[0], off[1]);
      f.peak_rate_deg_s = num(n, "peak_rate_deg_s", p);
      f.rise = num(n, "rise", p);
      f.flips = as<int>(n["flips"], p + ".flips");
      f.first_flip_time = num(n, "first_flip_time", p);
      f.flip_interval = num(n, "flip_interval", p);
      f.sway = num(n, "sway", p);
      f.sway_frequency = num(n, "sway_frequency", p);
      return std::make_unique<FlipTrajectory>(f);
    }
    if (s == "helix" || s == "circle")
    {
      const YAML::Node n = tr[s];
      const std::string p = "trajectory." + s;
      HelixTrajectoryParams h;
      if (s == "helix")
      {
        h.start_distance = num(n, "start_distance", p);
        h.end_distance = num(n, "end_distance", p);
      }
      else
        h.start_distance = h.end_distance = num(n, "distance", p);
      h.tilt_deg = num(n, "tilt_deg", p);
      h.turns = num(n, "turns", p);
      h.duration = num(n, "duration", p);
      return std::make_unique<HelixTrajectory>(h);
    }
    if (s == "linear")
    {
      const YAML::Node n = tr["linear"];
      const std::string p = "trajectory.linear";
      LinearTrajectoryParams l;
      l.start_position = vec3(n, "start_position", p);
      l.start_ypr_deg = vec3(n, "start_ypr_deg", p);
      l.end_position = vec3(n, "end_position", p);
      l.end_ypr_deg = vec3(n, "end_ypr_deg", p);
      l.duration = num(n, "duration", p);
      return std::make_unique<LinearTrajectory>(l);
    }
    if (s == "random")
    {
      const YAML::Node n = tr["random"];
      const std::string p = "trajectory.random";
      RandomTrajectoryParams r;
      r.distance = num(n, "distance", p);
      r.position_amplitude = vec3(n, "position_amplitude", p);
      r.ypr_amplitude_deg = vec3(n, "ypr_amplitude_deg", p);
      r.min_frequency = num(n, "min_frequency", p);
      r.max_frequency = num(n, "max_frequency", p);
      r.components = as<int>(n["components"], p + ".components");
      return std::make_unique<RandomTrajectory>(r, config.seed);
    }
    if (s == "file")
    {
      const std::string path = as<std::string>(tr["file"]["path"], "trajectory.file.path");
      if (path.empty())
        throw ConfigError("scenario 'file' needs trajectory.file.path (a TUM or CSV trajectory)");
      return std::make_unique<SampledTrajectory>(dvs_calibration::readTumTrajectory(path));
    }
  }
  catch (const TrajectoryError& e)
  {
    throw ConfigError(e.what());
  }
  catch (const dvs_calibration::TrajectoryFileError& e)
  {
    throw ConfigError(e.what());
  }
  throw ConfigError("unknown scenario '" + s + "' (known: flip, helix, circle, linear, random, file)");
}

void addSharedRunParams(dvs_driver::ParamTable& table, SimRunParams& p)
{
  table.add("duration", p.duration, "s", 0, 1e308, "simulated length (0: the scenario's natural length)");
  table.add("packet_period", p.packet_period, "s", 0, 10, "simulated time per event packet (ROS message, bag)")
      .min_exclusive = true;
}

dvs_driver::ParamTable simRunParamTable(SimRunParams& p)
{
  dvs_driver::ParamTable table("dvs_screen_sim configuration");
  addSharedRunParams(table, p);
  table.add("time_offset", p.time_offset, "s", 0, 1e308, "added to every output time stamp");
  table.add("groundtruth_rate", p.groundtruth_rate, "Hz", 0, 1e308, "ground-truth poses per second").min_exclusive = true;
  return table;
}

SimConfig resolveSimConfig(const std::string& scenario, const YAML::Node& overrides, std::optional<uint64_t> seed,
                           std::optional<double> duration)
{
  const auto& names = scenarioNames();
  if (std::find(names.begin(), names.end(), scenario) == names.end())
    throw ConfigError("unknown scenario '" + scenario + "' (known: flip, helix, circle, linear, random, file)");
  YAML::Node tree = defaultConfigTree(scenario);
  if (overrides && !overrides.IsNull())
    mergeInto(tree, overrides, "");
  tree["scenario"] = scenario;
  if (seed)
    tree["seed"] = *seed;
  if (duration)
    tree["duration"] = *duration;

  SimConfig c;
  c.scenario = scenario;
  c.seed = as<uint64_t>(tree["seed"], "seed");
  SimRunParams run;
  run.duration = num(tree, "duration", "");
  run.time_offset = num(tree, "time_offset", "");
  run.groundtruth_rate = num(tree, "groundtruth_rate", "");
  run.packet_period = num(tree, "packet_period", "");
  const std::string bad = simRunParamTable(run).validate();
  if (!bad.empty())
    throw ConfigError(bad);
  c.groundtruth_rate = run.groundtruth_rate;
  c.packet_period = run.packet_period;
  c.time_offset_ns = static_cast<int64_t>(std::llround(run.time_offset * 1e9));
  c.camera = resolveCamera(tree["camera"]);

  YAML::Node scene_node = tree["scene"];
  const std::string scene_file = as<std::string>(scene_node["file"], "scene.file");
  try
  {
    c.scene = scene_file.empty() ? sceneFromYaml(scene_node) : loadSceneYaml(scene_file);
  }
  catch (const SceneError& e)
  {
    throw ConfigError(e.what());
  }
  if (c.scene.polygons.empty() && c.scene.images.empty())
    throw ConfigError("scene.polygons and scene.images are empty: the simulated DVS would see a blank wall");
  YAML::Node resolved_scene = sceneToYaml(c.scene);
  resolved_scene["file"] = scene_file;
  tree["scene"] = resolved_scene;

  YAML::Node ev = tree["events"];
  c.events.threshold_on = num(ev, "threshold_on", "events");
  c.events.threshold_off = num(ev, "threshold_off", "events");
  c.events.min_threshold = num(ev, "min_threshold", "events");
  c.events.log_eps = num(ev, "log_eps", "events");
  c.events.noise = resolveNoise(ev["noise"]);
  YAML::Node sa = tree["sampling"];
  c.sampling.max_pixel_motion = num(sa, "max_pixel_motion", "sampling");
  c.sampling.min_dt = num(sa, "min_dt", "sampling");
  c.sampling.max_dt = num(sa, "max_dt", "sampling");
  c.imu = resolveImu(tree["imu"]);
  try
  {
    c.events.validate();
    c.sampling.validate();
  }
  catch (const std::invalid_argument& e)
  {
    throw ConfigError(e.what());
  }

  c.resolved = tree;
  // Resolve the duration: explicit, else the trajectory's natural length.
  c.duration = run.duration;
  if (c.duration == 0)
  {
    if (scenario == "random")
      c.duration = num(tree["trajectory"]["random"], "duration", "trajectory.random");
    else
      c.duration = makeTrajectory(c)->naturalDuration();
  }
  if (!(c.duration > 0))
    throw ConfigError("the resolved duration is not positive");
  // Refused up front rather than running until killed: the ground truth is kept in memory
  // (one pose per sample), and an hour of a flying DVS is ~15 GB of events.txt.
  constexpr double kMaxDuration = 3600.0;
  // The IMU samples and their true biases are kept in memory too.
  const double gt_megabytes = (c.duration * c.groundtruth_rate * sizeof(dvs_calibration::StampedPose) +
                               c.duration * c.imu.rate * 2 * sizeof(dvs_driver::ImuSample)) /
                              1e6;
  if (c.duration > kMaxDuration || gt_megabytes > 2000.0)
    throw ConfigError("duration " + std::to_string(c.duration) + " s is more than the simulator runs at once (at most " +
                      std::to_string(static_cast<int>(kMaxDuration)) + " s and 2000 MB of ground truth and IMU samples; this run's "
                      "ground truth and IMU samples would take " + std::to_string(static_cast<long long>(gt_megabytes)) +
                      " MB at " + std::to_string(c.groundtruth_rate) + " Hz): split it into shorter runs");
  tree["duration"] = c.duration;
  c.resolved = tree;
  return c;
}

SimConfig resolveSimConfigFile(const std::string& scenario, const std::string& config_path,
                               std::optional<uint64_t> seed, std::optional<double> duration)
{
  YAML::Node overrides;
  if (!config_path.empty())
  {
    try
    {
      overrides = YAML::LoadFile(config_path);
    }
    catch (const YAML::Exception& e)
    {
      throw ConfigError("cannot read configuration file '" + config_path + "': " + e.what());
    }
  }
  return resolveSimConfig(scenario, overrides, seed, duration);
}
}  // namespace dvs_screen_sim
