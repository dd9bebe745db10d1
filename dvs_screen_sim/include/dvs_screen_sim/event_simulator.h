#pragma once
// The software DVS: per-pixel log-intensity change detection on an area-correct rendering of a
// planar scene along a camera trajectory.
//
// Model (ESIM-like, see shared/reference/event-simulation-models.md):
//   L = log(I + log_eps) per pixel; each pixel keeps a reference level Lref (initially L at the
//   start, or a random level within one threshold with `random_initial_reference`). Whenever L
//   reaches Lref + C_on (ON) or Lref - C_off (OFF) an event is emitted and Lref moves by
//   exactly one threshold; event times are interpolated between the two samples bracketing the
//   crossing (linearly in I + eps, which is exact for an edge crossing the pixel at constant
//   speed; ESIM interpolates log I), so they are not quantised to the sampling.
//   Sampling is adaptive: the next sample is taken when the visible edges have moved at most
//   `max_pixel_motion` px (bounded by [min_dt, max_dt]; square-wave flicker edges are sampled
//   exactly). Only pixels in the band an edge sweeps are re-evaluated (the scene is piecewise
//   constant), unless an intensity modulation changes, which re-evaluates every pixel. A
//   refreshing image with a response_time (a monitor) changes linearly over that time: the
//   events of a refresh are timed along the ramp (exact for a camera still relative to it).
// Noise (each switchable, all driven by the seed, so the output is bit-for-bit reproducible):
//   fixed per-pixel threshold mismatch (Gaussian sigma, thresholds clamped >= min_threshold),
//   refractory period (events inside it are dropped, the reference still moves), latency with
//   Gaussian jitter (truncated at 0), background activity (Poisson per pixel, random polarity),
//   hot pixels (a fixed random set firing Poisson at a high rate, random polarity).
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/event.h>
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/scene_renderer.h>
#include <dvs_screen_sim/trajectory.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace dvs_screen_sim
{
struct NoiseConfig
{
  double threshold_sigma = 0.0;         ///< per-pixel fixed threshold mismatch (log units)
  double refractory_period = 0.0;       ///< [s]
  double latency = 0.0;                 ///< mean event latency [s]
  double latency_jitter = 0.0;          ///< std-dev of the latency [s]
  double background_rate = 0.0;         ///< background activity per pixel [Hz]
  double hot_pixel_fraction = 0.0;      ///< fraction of pixels that are hot
  double hot_pixel_rate = 0.0;          ///< [Hz] per hot pixel
  bool random_initial_reference = false;
};

/// Presets: "clean" (no noise), "realistic" (DVS128-like), "noisy". Throws std::invalid_argument
/// naming the known presets for any other name.
NoiseConfig noisePreset(const std::string& name);

struct EventModelConfig
{
  double threshold_on = 0.3;   ///< C+ (log units)
  double threshold_off = 0.3;  ///< C- (log units)
  double min_threshold = 0.01;
  double log_eps = 1e-3;
  NoiseConfig noise;
  /// Throws std::invalid_argument naming the bad parameter.
  void validate() const;
};

struct SamplingConfig
{
  double max_pixel_motion = 0.2;  ///< [px] between two samples
  double min_dt = 1e-6;           ///< [s]
  double max_dt = 1e-3;           ///< [s]
  void validate() const;
};

struct SimulationStats
{
  uint64_t samples = 0;
  uint64_t pixel_updates = 0;
  uint64_t signal_events = 0;
  uint64_t refractory_dropped = 0;
  uint64_t noise_events = 0;
};

class EventSimulator
{
public:
  EventSimulator(const dvs_calibration::CameraModel& camera, const Scene& scene, const EventModelConfig& model,
                 const SamplingConfig& sampling, uint64_t seed);

  /// (Re)start at time t0 on `trajectory` (kept by reference: it must outlive the simulation).
  /// Renders the first image and initialises the reference levels. Events get time stamps
  /// round(t * 1e9) + time_offset_ns.
  void start(const Trajectory& trajectory, double t0 = 0.0, int64_t time_offset_ns = 0);

  /// Simulate up to time t_end [s] and append, sorted by time, every event whose time stamp is
  /// final (earlier than the current simulation time; later ones wait for latency jitter).
  /// Samples are also taken at every whole millisecond of absolute time (time stamp incl. the
  /// offset), so splitting a run into advanceTo() calls at such times gives the same events.
  void advanceTo(double t_end, dvs_driver::EventVector& out);
  /// Append every pending event (call at the end).
  void flush(dvs_driver::EventVector& out);

  double currentTime() const { return t_; }
  const SimulationStats& stats() const { return stats_; }
  const SceneRenderer& renderer() const { return renderer_; }
  /// Per-pixel thresholds actually used (after mismatch).
  const std::vector<double>& thresholdsOn() const { return c_on_; }
  const std::vector<double>& thresholdsOff() const { return c_off_; }

private:
  void step(double t_next);
  void processPixel(int32_t idx, double t0, double t1);
  void setReference(size_t i, double l_ref);
  void emit(int64_t t_ns, int32_t idx, bool polarity);
  void addNoiseEvents(double t0, double t1);
  void releaseFinal(int64_t before_ns, dvs_driver::EventVector& out);
  int64_t toNs(double t) const;

  SceneRenderer renderer_;
  EventModelConfig model_;
  SamplingConfig sampling_;
  uint64_t seed_;
  int width_, height_;
  const Trajectory* trajectory_ = nullptr;
  int64_t time_offset_ns_ = 0;
  double t_ = 0;
  double dt_guess_ = 1e-4;
  bool pre_discontinuity_ = false;

  std::vector<double> i_last_;          ///< I + eps at the pixel's last update
  std::vector<double> l_ref_;           ///< reference log level
  std::vector<double> i_up_, i_down_;   ///< exp(l_ref + C_on), exp(l_ref - C_off)
  std::vector<double> c_on_, c_off_;
  std::vector<int64_t> last_event_ns_;
  std::vector<uint32_t> marks_;
  uint32_t mark_ = 0;
  std::vector<int32_t> band_prev_, band_now_, touched_;
  std::vector<int32_t> hot_pixels_;
  std::vector<double> polygon_intensity_;

  std::mt19937_64 rng_latency_, rng_background_, rng_hot_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  double next_background_t_ = 0, next_hot_t_ = 0;

  dvs_driver::EventVector pending_;
  SimulationStats stats_;
};

/// Convenience: simulate `trajectory` from t0 to t1 and return every event (sorted). E.g. a
/// flickering calibration screen from one pose: simulateEvents(camera, screen,
/// StaticTrajectory(T_world_camera), 0.0, 0.05, EventModelConfig(), SamplingConfig(), seed).
dvs_driver::EventVector simulateEvents(const dvs_calibration::CameraModel& camera, const Scene& scene,
                                       const Trajectory& trajectory, double t0, double t1,
                                       const EventModelConfig& model = EventModelConfig(),
                                       const SamplingConfig& sampling = SamplingConfig(), uint64_t seed = 0,
                                       SimulationStats* stats = nullptr);
}  // namespace dvs_screen_sim
