#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/event_simulator.h>
#include <dvs_screen_sim/sim_config.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

using namespace dvs_screen_sim;
using dvs_driver::EventVector;

namespace
{
dvs_calibration::CameraModel pinhole(int w, int h, double f)
{
  dvs_calibration::CameraIntrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = f;
  k.cx = (w - 1) / 2.0;
  k.cy = (h - 1) / 2.0;
  return dvs_calibration::CameraModel(k);
}

Scene halfPlaneScene()
{
  Scene s;
  s.background_reflectance = 0.9;
  ScenePolygon p;
  p.reflectance = 0.1;
  p.vertices = {{0, -10}, {10, -10}, {10, 10}, {0, 10}};  // black right of world x = 0
  s.polygons.push_back(p);
  s.finalize();
  return s;
}

EventModelConfig cleanModel()
{
  EventModelConfig m;
  m.noise = noisePreset("clean");
  return m;
}

EventVector simulate(const dvs_calibration::CameraModel& cam, const Scene& scene, const Trajectory& traj,
                     double duration, const EventModelConfig& model, uint64_t seed = 1,
                     SimulationStats* stats = nullptr)
{
  return simulateEvents(cam, scene, traj, 0.0, duration, model, SamplingConfig(), seed, stats);
}

void expectSortedInSensor(const EventVector& ev, int w, int h)
{
  for (size_t i = 0; i < ev.size(); ++i)
  {
    ASSERT_LT(ev[i].x, w);
    ASSERT_LT(ev[i].y, h);
    if (i > 0)
    {
      ASSERT_LE(ev[i - 1].t_ns, ev[i].t_ns) << "event " << i;
    }
  }
}

Pose facingWall(double x, double d)
{
  const Pose p = Pose::fromWorldCamera(lookingAtWallOrientation(), Eigen::Vector3d(x, 0, d));
  return p;
}

SimConfig cleanFlipConfig(double duration)
{
  return resolveSimConfig(
      "flip", YAML::Load("{events: {noise: {preset: clean}}, trajectory: {flip: {first_flip_time: 0.2}}}"), 3,
      duration);
}
}  // namespace

// One edge sweeping across the sensor: each pixel gets floor(log contrast / C) events, all of
// the edge's polarity, at the analytically known crossing times.
TEST(EventSimulator, OneEdgeGivesLogContrastOverThresholdEventsPerPixel)
{
  const auto cam = pinhole(64, 16, 60);
  LinearTrajectoryParams lp;
  lp.start_position = Eigen::Vector3d(-0.4, 0, 1);
  lp.end_position = Eigen::Vector3d(0.4, 0, 1);
  lp.start_ypr_deg = lp.end_ypr_deg = Eigen::Vector3d::Zero();
  lp.duration = 0.5;
  const LinearTrajectory traj(lp);
  const EventModelConfig model = cleanModel();
  const EventVector ev = simulate(cam, halfPlaneScene(), traj, 0.5, model);
  expectSortedInSensor(ev, 64, 16);
  const double eps = model.log_eps;
  const double expected = std::log((0.9 + eps) / (0.1 + eps)) / model.threshold_off;  // 7.29
  std::map<std::pair<int, int>, std::vector<const dvs_driver::Event*>> per_pixel;
  for (const auto& e : ev)
  {
    EXPECT_FALSE(e.polarity) << "white -> black must give OFF events";
    per_pixel[{e.x, e.y}].push_back(&e);
  }
  // The edge moves from column 55.5 to 7.5: columns 9..54 are crossed completely.
  const double l0 = std::log(0.9 + eps);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 64; ++x)
    {
      const auto it = per_pixel.find({x, y});
      const size_t n = it == per_pixel.end() ? 0 : it->second.size();
      if (x >= 9 && x <= 54)
      {
        EXPECT_LE(std::abs(static_cast<double>(n) - expected), 1.0) << x << "," << y;
        // Crossing times: coverage f_k with log(0.9 - 0.8 f_k + eps) = l0 - k C.
        for (size_t k = 0; k < n; ++k)
        {
          const double f = (0.9 + eps - std::exp(l0 - (k + 1) * model.threshold_off)) / 0.8;
          const double u = x + 0.5 - f;                // edge column at the crossing
          const double t = (55.5 - u) * 0.5 / 48.0;    // u(t) = 55.5 - 96 t
          // Exact (intensity is linear in time within a sample interval) unless the pixel becomes
          // fully covered inside the interval of the crossing (edge within 0.1 px = 1 ms of motion of
          // the pixel border): then within one sample interval (max_dt = 1 ms).
          const double tolerance = 1.0 - f > 0.1 ? 1e-5 : 1e-3;
          EXPECT_NEAR(static_cast<double>(it->second[k]->t_ns) * 1e-9, t, tolerance) << x << "," << y << " k=" << k;
        }
      }
      else if (x <= 5 || x >= 58)
      {
        EXPECT_EQ(n, 0u) << x << "," << y;
      }
    }
}

namespace
{
void expectEventsOnProjectedEdges(const SimConfig& config)
{
  const SimulationOutput out = runSimulation(config);
  const auto traj = makeTrajectory(config);
  const auto& cam = config.camera;
  ASSERT_GT(out.events.size(), 10000u);
  expectSortedInSensor(out.events, cam.width(), cam.height());
  const auto segments = mapSegments(config.scene);
  size_t near = 0, decided = 0, polarity_ok = 0, checked = 0;
  for (size_t i = 0; i < out.events.size(); i += 7)  // a subsample keeps the test fast
  {
    const auto& e = out.events[i];
    const double t = static_cast<double>(e.t_ns) * 1e-9;
    const Pose pose = traj->poseAt(t);
    ++checked;
    double best = 1e9;
    for (const auto& s : segments)
    {
      Eigen::Vector2d prev;
      bool have_prev = false;
      for (int j = 0; j <= 400; ++j)
      {
        const Eigen::Vector3d pw = s.a + (s.b - s.a) * (j / 400.0);
        Eigen::Vector2d px;
        if (!cam.project(pose.toCamera(pw), px))
        {
          have_prev = false;
          continue;
        }
        if (have_prev)
        {
          const Eigen::Vector2d d = px - prev, p(e.x - prev.x(), e.y - prev.y());
          const double u = std::clamp(p.dot(d) / std::max(d.squaredNorm(), 1e-12), 0.0, 1.0);
          best = std::min(best, (p - u * d).norm());
        }
        prev = px;
        have_prev = true;
      }
    }
    if (best <= 1.0)
      ++near;
    // Ground-truth polarity: does the pixel centre's wall point enter (OFF) or leave (ON) the square?
    auto inside = [&](double tt) {
      const Pose p = traj->poseAt(tt);
      const Eigen::Vector2d xn = cam.pixelToUndistortedNormalized(Eigen::Vector2d(e.x, e.y));
      const Eigen::Vector3d d = p.q_world_camera() * Eigen::Vector3d(xn.x(), xn.y(), 1.0);
      const Eigen::Vector3d w = p.p_world_camera() + (-p.p_world_camera().z() / d.z()) * d;
      return std::abs(w.x()) < 0.45 && std::abs(w.y()) < 0.45;
    };
    const bool before = inside(t - 0.002), after = inside(t + 0.002);
    if (before != after)
    {
      ++decided;
      if (e.polarity == before)  // leaving the black square = ON
        ++polarity_ok;
    }
  }
  std::printf("clean flip (%s): %.2f %% of events within 1 px of a projected edge, polarity right for %.2f %%\n",
              config.resolved["camera"]["preset"].as<std::string>().c_str(), 100.0 * near / checked, 100.0 * polarity_ok / std::max<size_t>(decided, 1));
  EXPECT_GE(static_cast<double>(near) / checked, 0.98) << near << " of " << checked;
  ASSERT_GT(decided, checked / 4);
  EXPECT_GE(static_cast<double>(polarity_ok) / decided, 0.98) << polarity_ok << " of " << decided;
}
}  // namespace

TEST(EventSimulator, CleanFlipEventsLieOnProjectedEdgesWithTheRightPolarity)
{
  expectEventsOnProjectedEdges(cleanFlipConfig(0.4));
}

TEST(EventSimulator, CleanFlipGeometryHoldsWithAStronglyDistortedLens)
{
  // DAVIS240 preset: k1 = -0.37 (strong barrel distortion), 240x180.
  expectEventsOnProjectedEdges(resolveSimConfig(
      "flip",
      YAML::Load("{camera: {preset: davis240}, events: {noise: {preset: clean}}, trajectory: {flip: {first_flip_time: "
                 "0.1}}}"),
      3, 0.2));
}

TEST(EventSimulator, SameSeedSameEventsOtherSeedOtherEvents)
{
  const SimConfig a = resolveSimConfig("flip", YAML::Load("{events: {noise: {preset: noisy}}}"), 5, 0.3);
  const SimConfig b = resolveSimConfig("flip", YAML::Load("{events: {noise: {preset: noisy}}}"), 6, 0.3);
  const SimulationOutput x = runSimulation(a), y = runSimulation(a), z = runSimulation(b);
  ASSERT_GT(x.events.size(), 1000u);
  EXPECT_EQ(x.events, y.events);
  EXPECT_NE(x.events, z.events);
  expectSortedInSensor(x.events, 128, 128);
  expectSortedInSensor(z.events, 128, 128);
}

TEST(EventSimulator, BackgroundActivityIsPoissonAtTheConfiguredRate)
{
  const auto cam = pinhole(64, 64, 60);
  const StaticTrajectory still(facingWall(0, 1));
  EventModelConfig m = cleanModel();
  m.noise.background_rate = 5.0;
  SimulationStats stats;
  const EventVector ev = simulate(cam, halfPlaneScene(), still, 1.0, m, 9, &stats);
  const double expected = 5.0 * 64 * 64;
  EXPECT_NEAR(static_cast<double>(ev.size()), expected, 5 * std::sqrt(expected));
  EXPECT_EQ(stats.signal_events, 0u);  // nothing moves
  expectSortedInSensor(ev, 64, 64);
  size_t on = 0;
  for (const auto& e : ev)
    on += e.polarity;
  EXPECT_NEAR(static_cast<double>(on), ev.size() / 2.0, 5 * std::sqrt(ev.size() / 4.0));
}

TEST(EventSimulator, HotPixelsAreAFixedSet)
{
  const auto cam = pinhole(64, 64, 60);
  const StaticTrajectory still(facingWall(0, 1));
  EventModelConfig m = cleanModel();
  m.noise.hot_pixel_fraction = 0.01;  // round(40.96) = 41 pixels
  m.noise.hot_pixel_rate = 100.0;
  const EventVector ev = simulate(cam, halfPlaneScene(), still, 0.5, m);
  std::set<std::pair<int, int>> pixels;
  for (const auto& e : ev)
    pixels.insert({e.x, e.y});
  EXPECT_EQ(pixels.size(), 41u);
  EXPECT_NEAR(static_cast<double>(ev.size()), 2050.0, 5 * std::sqrt(2050.0));
}

TEST(EventSimulator, RefractoryPeriodSpacesEventsOfAPixel)
{
  const SimConfig base = cleanFlipConfig(0.3);
  EventModelConfig m = base.events;
  m.noise.refractory_period = 300e-6;
  const auto traj = makeTrajectory(base);
  SimulationStats stats;
  const EventVector ev = simulate(base.camera, base.scene, *traj, 0.3, m, 1, &stats);
  EXPECT_GT(stats.refractory_dropped, 100u);
  std::map<int, int64_t> last;
  for (const auto& e : ev)
  {
    const int key = e.y * 128 + e.x;
    const auto it = last.find(key);
    if (it != last.end())
    {
      ASSERT_GE(e.t_ns - it->second, 300000) << "pixel " << e.x << "," << e.y;
    }
    last[key] = e.t_ns;
  }
}

TEST(EventSimulator, ThresholdMismatchAndLatencyJitter)
{
  const SimConfig base = cleanFlipConfig(0.3);
  EventModelConfig m = base.events;
  m.noise.threshold_sigma = 0.03;
  EventSimulator sim(base.camera, base.scene, m, base.sampling, 4);
  const auto traj = makeTrajectory(base);
  sim.start(*traj);
  double sum = 0, sum2 = 0;
  for (double c : sim.thresholdsOn())
  {
    sum += c;
    sum2 += c * c;
  }
  const double n = static_cast<double>(sim.thresholdsOn().size());
  EXPECT_NEAR(sum / n, 0.3, 0.002);
  EXPECT_NEAR(std::sqrt(sum2 / n - (sum / n) * (sum / n)), 0.03, 0.003);

  EventModelConfig jit = base.events;
  jit.noise.latency = 50e-6;
  jit.noise.latency_jitter = 20e-6;
  const EventVector clean = simulate(base.camera, base.scene, *traj, 0.3, base.events);
  const EventVector late = simulate(base.camera, base.scene, *traj, 0.3, jit);
  ASSERT_EQ(clean.size(), late.size());  // latency moves events, it does not drop them
  expectSortedInSensor(late, 128, 128);
  double mean_delay = 0;
  for (size_t i = 0; i < clean.size(); ++i)
    mean_delay += static_cast<double>(late[i].t_ns - clean[i].t_ns);
  EXPECT_NEAR(mean_delay / clean.size() * 1e-9, 50e-6, 5e-6);
}

TEST(EventSimulator, SquareWaveFlickerFiresAtTheEdgesOfTheWave)
{
  const auto cam = pinhole(32, 32, 40);
  Scene s;
  s.background_reflectance = 0.5;
  ScenePolygon p;
  p.vertices = {{-0.1, -0.1}, {0.1, -0.1}, {0.1, 0.1}, {-0.1, 0.1}};
  p.modulation.type = IntensityModulation::Type::Square;
  p.modulation.frequency_hz = 200;
  p.modulation.low = 0.2;
  p.modulation.high = 0.8;
  s.polygons.push_back(p);
  s.finalize();
  const StaticTrajectory still(facingWall(0, 1));
  const EventVector ev = simulate(cam, s, still, 0.02, cleanModel());
  ASSERT_GT(ev.size(), 100u);
  size_t on = 0;
  for (const auto& e : ev)
  {
    // Edges every 2.5 ms: rising (ON) at multiples of 5 ms, falling (OFF) half-way.
    const double phase = std::fmod(static_cast<double>(e.t_ns), 5e6);
    const bool rising = phase < 20 || phase > 5e6 - 20;
    const bool falling = std::abs(phase - 2.5e6) < 20;
    ASSERT_TRUE(rising || falling) << "event at " << e.t_ns << " ns is not at a wave edge";
    EXPECT_EQ(e.polarity, rising);
    on += e.polarity;
  }
  EXPECT_GT(on, 0u);
  EXPECT_LT(on, ev.size());
}

TEST(EventSimulator, RefreshingScreenImageFiresAtFrameChangesOnly)
{
  const auto cam = pinhole(32, 32, 40);
  Scene s;
  s.background_reflectance = 0.2;
  SceneImage im;
  im.width = 4;
  im.height = 4;
  im.texels.assign(16, 0.2f);
  im.top_left = Eigen::Vector2d(-0.2, 0.2);
  im.size = Eigen::Vector2d(0.4, 0.4);
  im.update_period = 1.0 / 60.0;  // a 60 Hz monitor: frame k shows texel k % 16 bright
  im.update = [](int64_t frame, std::vector<float>& texels) {
    std::fill(texels.begin(), texels.end(), 0.2f);
    texels[static_cast<size_t>(frame % 16)] = 0.8f;
  };
  s.images.push_back(im);
  s.finalize();
  const StaticTrajectory still(facingWall(0, 1));
  const EventVector ev = simulate(cam, s, still, 0.1, cleanModel());
  ASSERT_GT(ev.size(), 100u);
  for (const auto& e : ev)
  {
    const double frames = static_cast<double>(e.t_ns) * 1e-9 * 60.0;
    EXPECT_NEAR(frames, std::round(frames), 1e-5) << "event at " << e.t_ns << " ns is not at a refresh";
  }
}

// A monitor with a response time: a content change reaches the new luminance linearly over
// response_time, so each pixel's events of a change are spread along that ramp in the order of
// their levels (log-spaced levels on a linear ramp: known times), and a refractory period that
// eats all but one event of an instantaneous step keeps them.
TEST(EventSimulator, MonitorResponseTimeSpreadsAFrameChangeAlongALinearRamp)
{
  const auto cam = pinhole(16, 16, 20);
  auto makeScene = [](double response) {
    Scene s;
    s.background_reflectance = 0.02;
    SceneImage im;
    im.width = 2;
    im.height = 2;
    im.texels.assign(4, 0.02f);
    im.top_left = Eigen::Vector2d(-1.0, 1.0);
    im.size = Eigen::Vector2d(2.0, 2.0);  // covers the whole view
    im.update_period = 1.0 / 60.0;
    im.response_time = response;
    im.update = [](int64_t frame, std::vector<float>& texels) {
      std::fill(texels.begin(), texels.end(), frame % 2 ? 0.9f : 0.02f);  // black / white every refresh
    };
    s.images.push_back(im);
    s.finalize();
    return s;
  };
  const StaticTrajectory still(facingWall(0, 1));
  const double period = 1.0 / 60.0, response = 0.005;
  EventModelConfig m = cleanModel();
  const EventVector step = simulate(cam, makeScene(0.0), still, 1.5 * period, m);
  const EventVector ramp = simulate(cam, makeScene(response), still, 1.5 * period, m);
  // Same number of events (the same levels are crossed), per pixel at the known ramp times.
  ASSERT_EQ(step.size(), ramp.size());
  ASSERT_GT(ramp.size(), 16u * 16u * 10u);
  const double i0 = 0.02 + m.log_eps, i1 = 0.9 + m.log_eps;
  std::map<int, std::vector<int64_t>> on_times;
  for (const auto& e : ramp)
  {
    ASSERT_TRUE(e.polarity);  // the one change is black -> white (at 1/60 s)
    on_times[e.y * 16 + e.x].push_back(e.t_ns);
  }
  ASSERT_EQ(on_times.size(), 256u);
  for (const auto& [pixel, times] : on_times)
  {
    ASSERT_GE(times.size(), 10u);
    for (size_t k = 0; k < times.size(); ++k)
    {
      const double level = i0 * std::exp(m.threshold_on * static_cast<double>(k + 1));  // ON level k + 1
      const double expected = period + response * (level - i0) / (i1 - i0);
      EXPECT_NEAR(times[k] * 1e-9, expected, 2e-7) << "pixel " << pixel << " event " << k;
    }
  }
  // A refractory period: an instantaneous step keeps one event per pixel, the ramp nearly all.
  m.noise.refractory_period = 50e-6;
  EXPECT_EQ(simulate(cam, makeScene(0.0), still, 1.5 * period, m).size(), 256u);
  EXPECT_GT(simulate(cam, makeScene(response), still, 1.5 * period, m).size(), ramp.size() * 8 / 10);
}

TEST(Scene, ResponseTimeLongerThanTheRefreshIsRejected)
{
  Scene s;
  SceneImage im;
  im.width = im.height = 1;
  im.texels = {0.5f};
  im.update_period = 0.01;
  im.update = [](int64_t, std::vector<float>&) {};
  im.response_time = 0.02;
  s.images.push_back(im);
  EXPECT_THROW(s.finalize(), SceneError);
  s.images[0].response_time = 0.01;
  EXPECT_NO_THROW(s.finalize());
}
