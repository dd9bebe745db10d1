#include <dvs_screen_sim/event_simulator.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dvs_screen_sim
{
namespace
{
// A level reached exactly (e.g. a pixel returning to the intensity it started from after n OFF
// and n ON events, ref + n C == L) fires: without this tolerance, rounding would decide.
constexpr double kLevelTolerance = 1e-9;
constexpr int64_t kSampleGridNs = 1000000;

uint64_t splitmix64(uint64_t x)
{
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

void requireNonNegative(double v, const char* name)
{
  if (!(v >= 0) || !std::isfinite(v))
    throw std::invalid_argument(std::string(name) + " must be a finite number >= 0 (got " + std::to_string(v) + ")");
}

bool eventLess(const dvs_driver::Event& a, const dvs_driver::Event& b)
{
  if (a.t_ns != b.t_ns)
    return a.t_ns < b.t_ns;
  if (a.y != b.y)
    return a.y < b.y;
  if (a.x != b.x)
    return a.x < b.x;
  return a.polarity < b.polarity;
}
}  // namespace

NoiseConfig noisePreset(const std::string& name)
{
  NoiseConfig n;
  if (name == "clean")
    return n;
  if (name == "realistic")
  {
    n.threshold_sigma = 0.03;
    n.refractory_period = 50e-6;
    n.latency = 15e-6;
    n.latency_jitter = 10e-6;
    n.background_rate = 0.1;
    n.hot_pixel_fraction = 0.001;
    n.hot_pixel_rate = 10.0;
    n.random_initial_reference = true;
    return n;
  }
  if (name == "noisy")
  {
    n.threshold_sigma = 0.06;
    n.refractory_period = 200e-6;
    n.latency = 100e-6;
    n.latency_jitter = 50e-6;
    n.background_rate = 1.0;
    n.hot_pixel_fraction = 0.005;
    n.hot_pixel_rate = 50.0;
    n.random_initial_reference = true;
    return n;
  }
  throw std::invalid_argument("unknown noise preset '" + name + "' (known: clean, realistic, noisy)");
}

void EventModelConfig::validate() const
{
  if (!(threshold_on > 0))
    throw std::invalid_argument("events.threshold_on must be > 0");
  if (!(threshold_off > 0))
    throw std::invalid_argument("events.threshold_off must be > 0");
  if (!(min_threshold > 0))
    throw std::invalid_argument("events.min_threshold must be > 0");
  if (!(log_eps > 0))
    throw std::invalid_argument("events.log_eps must be > 0");
  requireNonNegative(noise.threshold_sigma, "noise.threshold_sigma");
  requireNonNegative(noise.refractory_period, "noise.refractory_period");
  requireNonNegative(noise.latency, "noise.latency");
  requireNonNegative(noise.latency_jitter, "noise.latency_jitter");
  requireNonNegative(noise.background_rate, "noise.background_rate");
  requireNonNegative(noise.hot_pixel_rate, "noise.hot_pixel_rate");
  if (!(noise.hot_pixel_fraction >= 0 && noise.hot_pixel_fraction <= 1))
    throw std::invalid_argument("noise.hot_pixel_fraction must be in [0, 1]");
}

void SamplingConfig::validate() const
{
  if (!(max_pixel_motion > 0))
    throw std::invalid_argument("sampling.max_pixel_motion must be > 0");
  if (!(min_dt > 0))
    throw std::invalid_argument("sampling.min_dt must be > 0");
  if (!(max_dt >= min_dt))
    throw std::invalid_argument("sampling.max_dt must be >= sampling.min_dt");
}

EventSimulator::EventSimulator(const dvs_calibration::CameraModel& camera, const Scene& scene,
                               const EventModelConfig& model, const SamplingConfig& sampling, uint64_t seed)
  : renderer_(camera, scene), model_(model), sampling_(sampling), seed_(seed), width_(camera.width()),
    height_(camera.height())
{
  model_.validate();
  sampling_.validate();
  const size_t n = static_cast<size_t>(width_) * height_;
  i_last_.assign(n, 0.0);
  l_ref_.assign(n, 0.0);
  i_up_.assign(n, 0.0);
  i_down_.assign(n, 0.0);
  c_on_.assign(n, model_.threshold_on);
  c_off_.assign(n, model_.threshold_off);
  last_event_ns_.assign(n, std::numeric_limits<int64_t>::min() / 2);
  marks_.assign(n, 0);
  band_prev_.reserve(n);
  band_now_.reserve(n);
  touched_.reserve(n);
}

int64_t EventSimulator::toNs(double t) const
{
  return static_cast<int64_t>(std::llround(t * 1e9)) + time_offset_ns_;
}

void EventSimulator::start(const Trajectory& trajectory, double t0, int64_t time_offset_ns)
{
  trajectory_ = &trajectory;
  time_offset_ns_ = time_offset_ns;
  t_ = t0;
  dt_guess_ = sampling_.min_dt * 10;
  stats_ = SimulationStats();
  pending_.clear();
  const size_t n = i_last_.size();
  const auto& noise = model_.noise;

  std::mt19937_64 rng_mismatch(splitmix64(seed_ + 1));
  std::mt19937_64 rng_reference(splitmix64(seed_ + 2));
  rng_latency_.seed(splitmix64(seed_ + 3));
  rng_background_.seed(splitmix64(seed_ + 4));
  rng_hot_.seed(splitmix64(seed_ + 5));
  normal_.reset();
  uniform_.reset();
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (size_t i = 0; i < n; ++i)
  {
    c_on_[i] = model_.threshold_on;
    c_off_[i] = model_.threshold_off;
    if (noise.threshold_sigma > 0)
    {
      c_on_[i] = std::max(model_.min_threshold, model_.threshold_on + noise.threshold_sigma * normal(rng_mismatch));
      c_off_[i] = std::max(model_.min_threshold, model_.threshold_off + noise.threshold_sigma * normal(rng_mismatch));
    }
  }
  renderer_.setState(trajectory.poseAt(t0), t0);
  polygon_intensity_.resize(renderer_.scene().polygons.size());
  for (size_t k = 0; k < polygon_intensity_.size(); ++k)
    polygon_intensity_[k] = renderer_.scene().polygonIntensity(k, t0);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
    {
      const size_t i = static_cast<size_t>(y) * width_ + x;
      i_last_[i] = renderer_.pixelIntensity(x, y) + model_.log_eps;
      double ref = std::log(i_last_[i]);
      if (noise.random_initial_reference)
        ref += -c_on_[i] + (c_on_[i] + c_off_[i]) * uniform(rng_reference);  // L - ref < C_on, ref - L < C_off
      setReference(i, ref);
      last_event_ns_[i] = std::numeric_limits<int64_t>::min() / 2;
    }
  ++mark_;
  band_prev_.clear();
  renderer_.appendEdgePixels(band_prev_, marks_, mark_);

  hot_pixels_.clear();
  const size_t n_hot = static_cast<size_t>(std::llround(noise.hot_pixel_fraction * static_cast<double>(n)));
  if (n_hot > 0 && noise.hot_pixel_rate > 0)
  {
    std::vector<int32_t> all(n);
    for (size_t i = 0; i < n; ++i)
      all[i] = static_cast<int32_t>(i);
    for (size_t i = 0; i < n_hot; ++i)
    {
      const size_t j = i + static_cast<size_t>(uniform(rng_hot_) * static_cast<double>(n - i));
      std::swap(all[i], all[std::min(j, n - 1)]);
      hot_pixels_.push_back(all[i]);
    }
  }
  const double bg_total = noise.background_rate * static_cast<double>(n);
  next_background_t_ = bg_total > 0 ? t0 - std::log(1.0 - uniform_(rng_background_)) / bg_total
                                    : std::numeric_limits<double>::infinity();
  const double hot_total = noise.hot_pixel_rate * static_cast<double>(hot_pixels_.size());
  next_hot_t_ =
      hot_total > 0 ? t0 - std::log(1.0 - uniform_(rng_hot_)) / hot_total : std::numeric_limits<double>::infinity();
}

void EventSimulator::advanceTo(double t_end, dvs_driver::EventVector& out)
{
  if (!trajectory_)
    throw std::logic_error("EventSimulator::advanceTo called before start()");
  const bool time_varying = renderer_.scene().timeVarying();
  while (t_ < t_end - 1e-12)
  {
    double dt = dt_guess_;
    double t_next = 0, motion = 0;
    // Samples also fall on every whole millisecond of absolute time (time stamps incl. the
    // offset): the results then do not depend on how the caller splits the simulation into
    // advanceTo() calls, as long as it splits on that grid.
    const int64_t now_ns = toNs(t_);
    const int64_t grid_ns = (now_ns >= 0 ? now_ns / kSampleGridNs + 1 : -((-now_ns) / kSampleGridNs)) * kSampleGridNs;
    const double t_grid = static_cast<double>(grid_ns - time_offset_ns_) * 1e-9;
    const double t_limit = std::min(t_end, t_grid);
    for (;;)
    {
      t_next = std::min(t_ + dt, t_limit);
      motion = renderer_.maxImageMotion(trajectory_->poseAt(t_next));
      if (motion <= sampling_.max_pixel_motion || dt <= sampling_.min_dt)
        break;
      dt = std::max(sampling_.min_dt, dt * 0.8 * sampling_.max_pixel_motion / motion);
    }
    const double grow = motion > 0 ? 0.8 * sampling_.max_pixel_motion / motion : 2.0;
    dt_guess_ = std::clamp(dt * std::min(2.0, grow), sampling_.min_dt, sampling_.max_dt);
    if (time_varying)
    {
      // Sample just before and exactly at every square-wave edge.
      const double td = renderer_.scene().nextDiscontinuity(t_);
      if (td <= t_next)
        t_next = td - 1e-8 > t_ + 1e-12 ? td - 1e-8 : td;
    }
    step(t_next);
    if (pending_.size() > (1u << 16))
      releaseFinal(toNs(t_), out);
  }
  releaseFinal(toNs(t_), out);
}

void EventSimulator::flush(dvs_driver::EventVector& out)
{
  releaseFinal(std::numeric_limits<int64_t>::max(), out);
}

void EventSimulator::step(double t_next)
{
  const double t0 = t_;
  renderer_.setState(trajectory_->poseAt(t_next), t_next);
  ++stats_.samples;
  bool intensity_changed = false;
  for (size_t k = 0; k < polygon_intensity_.size(); ++k)
  {
    const double v = renderer_.scene().polygonIntensity(k, t_next);
    if (v != polygon_intensity_[k])
      intensity_changed = true;
    polygon_intensity_[k] = v;
  }
  ++mark_;
  band_now_.clear();
  renderer_.appendEdgePixels(band_now_, marks_, mark_);
  if (intensity_changed || renderer_.imagesChanged())
  {
    // A monitor's content update is not instantaneous: the luminance moves linearly to the new
    // content over its response time from the update (t_next), so the events of the change are
    // timed along that ramp (they wait in pending_ until simulated time passes them).
    const double ramp = renderer_.contentTransition();
    const double r0 = ramp > 0 ? t_next : t0, r1 = ramp > 0 ? t_next + ramp : t_next;
    const int32_t n = width_ * height_;
    for (int32_t idx = 0; idx < n; ++idx)
      processPixel(idx, r0, r1);
  }
  else
  {
    for (int32_t idx : band_now_)
      processPixel(idx, t0, t_next);
    for (int32_t idx : band_prev_)
      if (marks_[static_cast<size_t>(idx)] != mark_)
      {
        marks_[static_cast<size_t>(idx)] = mark_;
        processPixel(idx, t0, t_next);
      }
  }
  std::swap(band_prev_, band_now_);
  addNoiseEvents(t0, t_next);
  t_ = t_next;
}

void EventSimulator::processPixel(int32_t idx, double t0, double t1)
{
  // Works in the intensity domain: the pixel's next ON / OFF levels exp(Lref +- C) are kept
  // precomputed, so an update without an event costs no log or exp.
  ++stats_.pixel_updates;
  const size_t i = static_cast<size_t>(idx);
  const double i_new = renderer_.pixelIntensity(idx % width_, idx / width_) + model_.log_eps;
  const double i_old = i_last_[i];
  i_last_[i] = i_new;
  const double di = i_new - i_old;
  if (di == 0.0)
    return;
  // Crossing times: the intensity (I + eps) is interpolated linearly between the two samples
  // (exact for an edge moving at constant speed across the pixel, where the covered area, hence
  // I, is linear in time; interpolating log I instead biases the times of the darkest crossings).
  const double span = t1 - t0;
  if (i_new >= i_up_[i])
  {
    double ref = l_ref_[i], up = i_up_[i];
    const double c = c_on_[i];
    do
    {
      emit(toNs(t0 + std::clamp((up - i_old) / di, 0.0, 1.0) * span), idx, true);
      ref += c;
      up = std::exp(ref + c - kLevelTolerance);
    } while (i_new >= up);
    setReference(i, ref);
  }
  else if (i_new <= i_down_[i])
  {
    double ref = l_ref_[i], down = i_down_[i];
    const double c = c_off_[i];
    do
    {
      emit(toNs(t0 + std::clamp((down - i_old) / di, 0.0, 1.0) * span), idx, false);
      ref -= c;
      down = std::exp(ref - c + kLevelTolerance);
    } while (i_new <= down);
    setReference(i, ref);
  }
}

void EventSimulator::setReference(size_t i, double l_ref)
{
  l_ref_[i] = l_ref;
  i_up_[i] = std::exp(l_ref + c_on_[i] - kLevelTolerance);
  i_down_[i] = std::exp(l_ref - c_off_[i] + kLevelTolerance);
}

void EventSimulator::emit(int64_t t_ns, int32_t idx, bool polarity)
{
  const auto& noise = model_.noise;
  const size_t i = static_cast<size_t>(idx);
  if (noise.refractory_period > 0)
  {
    if (static_cast<double>(t_ns - last_event_ns_[i]) < noise.refractory_period * 1e9)
    {
      ++stats_.refractory_dropped;
      return;
    }
    last_event_ns_[i] = t_ns;
  }
  if (noise.latency > 0 || noise.latency_jitter > 0)
  {
    const double lat = std::max(0.0, noise.latency + noise.latency_jitter * normal_(rng_latency_));
    t_ns += static_cast<int64_t>(std::llround(lat * 1e9));
  }
  ++stats_.signal_events;
  pending_.push_back({t_ns, static_cast<uint16_t>(idx % width_), static_cast<uint16_t>(idx / width_), polarity});
}

void EventSimulator::addNoiseEvents(double t0, double t1)
{
  (void)t0;
  const auto& noise = model_.noise;
  const double n = static_cast<double>(width_) * height_;
  const double bg_total = noise.background_rate * n;
  while (next_background_t_ <= t1)
  {
    const int32_t idx = std::min(static_cast<int32_t>(uniform_(rng_background_) * n), width_ * height_ - 1);
    const bool pol = uniform_(rng_background_) < 0.5;
    pending_.push_back({toNs(next_background_t_), static_cast<uint16_t>(idx % width_),
                        static_cast<uint16_t>(idx / width_), pol});
    ++stats_.noise_events;
    next_background_t_ -= std::log(1.0 - uniform_(rng_background_)) / bg_total;
  }
  const double hot_total = noise.hot_pixel_rate * static_cast<double>(hot_pixels_.size());
  while (next_hot_t_ <= t1)
  {
    const size_t h = std::min(static_cast<size_t>(uniform_(rng_hot_) * static_cast<double>(hot_pixels_.size())),
                              hot_pixels_.size() - 1);
    const int32_t idx = hot_pixels_[h];
    const bool pol = uniform_(rng_hot_) < 0.5;
    pending_.push_back({toNs(next_hot_t_), static_cast<uint16_t>(idx % width_), static_cast<uint16_t>(idx / width_),
                        pol});
    ++stats_.noise_events;
    next_hot_t_ -= std::log(1.0 - uniform_(rng_hot_)) / hot_total;
  }
}

void EventSimulator::releaseFinal(int64_t before_ns, dvs_driver::EventVector& out)
{
  if (pending_.empty())
    return;
  std::sort(pending_.begin(), pending_.end(), eventLess);
  auto it = std::lower_bound(pending_.begin(), pending_.end(), before_ns,
                             [](const dvs_driver::Event& e, int64_t t) { return e.t_ns < t; });
  out.insert(out.end(), pending_.begin(), it);
  pending_.erase(pending_.begin(), it);
}

dvs_driver::EventVector simulateEvents(const dvs_calibration::CameraModel& camera, const Scene& scene,
                                       const Trajectory& trajectory, double t0, double t1,
                                       const EventModelConfig& model, const SamplingConfig& sampling, uint64_t seed,
                                       SimulationStats* stats)
{
  EventSimulator sim(camera, scene, model, sampling, seed);
  dvs_driver::EventVector events;
  sim.start(trajectory, t0);
  sim.advanceTo(t1, events);
  sim.flush(events);
  if (stats)
    *stats = sim.stats();
  return events;
}
}  // namespace dvs_screen_sim
