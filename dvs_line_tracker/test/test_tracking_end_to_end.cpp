// End to end on the suite's software DVS (dvs_screen_sim): accuracy on the flip and the circle,
// and robustness (background noise, a 2000 deg/s flip). Accuracy bounds are the figures this
// implementation reaches with margin; BENCHMARKS.md sets them beside the targets.
#include "tracking_test_support.h"

#include "synthetic_events.h"
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/sim_config.h>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

using namespace dvs_line_tracker;

namespace
{
struct Simulated
{
  dvs_screen_sim::SimConfig config;
  dvs_screen_sim::SimulationOutput output;
  dvs_calibration::Trajectory ground_truth;
};

Simulated simulate(const std::string& scenario, const std::string& overrides_yaml)
{
  Simulated s;
  s.config = dvs_screen_sim::resolveSimConfig(scenario, YAML::Load(overrides_yaml));
  s.output = dvs_screen_sim::runSimulation(s.config);
  for (const auto& g : s.output.groundtruth)
    s.ground_truth.push_back(g);  // the simulator writes the suite's one stamped pose
  return s;
}

double firstEventTime(const dvs_driver::EventVector& events) { return events.front().t_ns * 1e-9; }

constexpr double kDeg = M_PI / 180.0;
}  // namespace

// Track a simulated sequence with the default parameters; prints and returns the accuracy.
struct Tracked
{
  Simulated sim;
  TrackingRun run;
  dvs_calibration::AccuracyReport accuracy;
};

static Tracked trackSimulated(const std::string& label, const std::string& scenario, const std::string& overrides_yaml)
{
  Tracked t;
  t.sim = simulate(scenario, overrides_yaml);
  LineTracker tracker(t.sim.config.camera, defaultSquareMap());
  t.run = runTracker(tracker, t.sim.output.events);
  t.accuracy = dvs_calibration::evaluateTrajectory(t.run.estimates, t.sim.ground_truth, 0.05);
  const dvs_calibration::AccuracyReport& r = t.accuracy;
  std::printf("%s: first pose %.3f s, RMS %.2f cm %.2f deg, max %.2f cm %.2f deg\n", label.c_str(),
              r.first_estimate_s, 100 * r.rms_position_m, r.rms_orientation_rad / kDeg, 100 * r.max_position_m,
              r.max_orientation_rad / kDeg);
  return t;
}

// Sequences several tests use: simulated and tracked once per test binary, on first use.
static const Tracked& flipAt2m()
{
  static const Tracked t = trackSimulated("flip 2 m", "flip", "trajectory: {flip: {distance: 2.0, peak_rate_deg_s: 1200}}");
  return t;
}
static const Tracked& circleAt2_5m()
{
  static const Tracked t = trackSimulated("circle 2.5 m", "circle", "trajectory: {circle: {distance: 2.5}}\nduration: 2.0");
  return t;
}

TEST(EndToEnd, Flip1200DegPerSecondAt2m)
{
  const Tracked& t = flipAt2m();
  const dvs_calibration::AccuracyReport& r = t.accuracy;
  ASSERT_FALSE(t.run.estimates.empty());
  // First pose within 0.25 s of the first events.
  EXPECT_LT(t.run.estimates.front().t - firstEventTime(t.sim.output.events), 0.25);
  EXPECT_EQ(r.samples_tracked, r.samples);  // 100 % tracked
  EXPECT_EQ(t.run.stats.losses, 0u);
  EXPECT_LT(r.rms_position_m, 0.022);  // measured 1.95 cm (2026-11-21; 4.04 cm before the edge model; seeds 1-5: 1.72-2.09)
  EXPECT_LT(r.rms_orientation_rad, 1.5 * kDeg);  // the target
  EXPECT_LT(r.max_position_m, 0.10);   // the target; measured 4.5 cm
  EXPECT_LT(r.max_orientation_rad, 6 * kDeg);
  EXPECT_EQ(t.run.final_state, TrackerState::kTracking);
}

// Closer, the square fills more of the view and two corners leave it at the top of the rise:
// the partly visible sides carry the pose (stale events of the parts that left are dropped).
TEST(EndToEnd, Flip1200DegPerSecondAt1_5m)
{
  const Tracked t = trackSimulated("flip 1.5 m", "flip", "trajectory: {flip: {distance: 1.5, peak_rate_deg_s: 1200}}");
  const dvs_calibration::AccuracyReport& r = t.accuracy;
  ASSERT_FALSE(t.run.estimates.empty());
  EXPECT_EQ(r.samples_tracked, r.samples);
  EXPECT_EQ(t.run.stats.losses, 0u);
  EXPECT_LT(r.rms_position_m, 0.02);   // the target; measured 1.11 cm (2026-11-21)
  EXPECT_LT(r.rms_orientation_rad, 1.5 * kDeg);
  EXPECT_LT(r.max_position_m, 0.10);   // the target; measured 3.7 cm
  EXPECT_LT(r.max_orientation_rad, 6 * kDeg);
}

// At 1 m most of the square leaves the view at the top of the rise: the partial-view damping
// steadies the pose on the few, short visible sides.
TEST(EndToEnd, Flip1200DegPerSecondAt1m)
{
  const Tracked t = trackSimulated("flip 1 m", "flip", "trajectory: {flip: {distance: 1.0, peak_rate_deg_s: 1200}}");
  const dvs_calibration::AccuracyReport& r = t.accuracy;
  ASSERT_FALSE(t.run.estimates.empty());
  EXPECT_EQ(r.samples_tracked, r.samples);
  EXPECT_LT(r.rms_position_m, 0.02);   // the target; measured 1.50 cm (2026-11-21; 2.58 cm without the partial-view damping)
  EXPECT_LT(r.rms_orientation_rad, 1.5 * kDeg);
  EXPECT_LT(r.max_position_m, 0.10);   // the target; measured 3.0 cm
  EXPECT_LT(r.max_orientation_rad, 10 * kDeg);
}

TEST(EndToEnd, CircleAt2_5m)
{
  const Tracked& t = circleAt2_5m();
  const dvs_calibration::AccuracyReport& r = t.accuracy;
  ASSERT_FALSE(t.run.estimates.empty());
  EXPECT_EQ(r.samples_tracked, r.samples);
  EXPECT_LT(r.rms_position_m, 0.03);   // the target; measured 2.2 cm (2026-11-21)
  EXPECT_LT(r.rms_orientation_rad, 2.0 * kDeg);  // the target
  EXPECT_LT(r.max_position_m, 0.09);   // measured 7.9 cm
}

// Mean position error along the camera's optical axis (m; < 0: the estimate is farther from the
// scene than the truth), at every tracked ground-truth sample.
static double meanDepthError(const dvs_calibration::Trajectory& estimates, const dvs_calibration::Trajectory& ground_truth)
{
  double sum = 0;
  int n = 0;
  size_t j = 0;
  for (const auto& gt : ground_truth)
  {
    if (estimates.empty() || gt.t < estimates.front().t)
      continue;
    while (j + 1 < estimates.size() && estimates[j + 1].t <= gt.t)
      ++j;
    if (gt.t - estimates[j].t > 0.05)
      continue;
    sum += (gt.T_world_camera.R_camera_world * (estimates[j].T_world_camera.p_world_camera() - gt.T_world_camera.p_world_camera())).z();
    ++n;
  }
  return n > 0 ? sum / n : 0.0;
}

// The dark square's edge events lie on their dark (inner) side: used where they are, the square
// looks smaller and the camera farther away. The learned dark-side offset removes that bias.
TEST(EndToEnd, EdgeOffsetCorrectionRemovesTheDepthBias)
{
  const Simulated& sim = circleAt2_5m().sim;  // tracked there with the default parameters: corrected
  const double bias_corrected = meanDepthError(circleAt2_5m().run.estimates, sim.ground_truth);
  LineTrackerParams params;
  params.edge_run_model = false;
  params.edge_offset_px = 0;
  LineTracker uncorrected(sim.config.camera, defaultSquareMap(), params);
  const double bias_uncorrected =
      meanDepthError(runTracker(uncorrected, sim.output.events).estimates, sim.ground_truth);
  std::printf("circle 2.5 m: mean depth error %.2f cm corrected, %.2f cm uncorrected\n", 100 * bias_corrected,
              100 * bias_uncorrected);
  EXPECT_LT(bias_uncorrected, -0.010);
  EXPECT_LT(std::abs(bias_corrected), 0.006);
}

// Per event, against the ground-truth edge at the event's time: the run model places the edge
// inside the firing pixel (edge_run_model.h) far better than the constant dark-side offset.
TEST(EndToEnd, RunModelPlacesEventsOnTheirEdge)
{
  const Simulated& sim = flipAt2m().sim;  // the flip at 2 m, 1200 deg/s (the defaults)
  const auto& cam = sim.config.camera;
  const auto& in = cam.intrinsics();
  const PinholeK k{in.fx, in.fy, in.cx, in.cy};
  const LineMap map = defaultSquareMap();
  EdgeRunModelParams params;
  params.contrast_threshold = 0.3;  // the simulator's
  EdgeRunModel run_model(cam.width(), cam.height(), params);
  params.enabled = false;
  EdgeRunModel constant(cam.width(), cam.height(), params);
  double sq_run = 0, sq_constant = 0, sq_centre = 0;
  int n = 0;
  const auto& gt = sim.ground_truth;
  for (const auto& e : sim.output.events)
  {
    const double run_offset = run_model.update(e.x, e.y, e.polarity);
    const double constant_offset = constant.update(e.x, e.y, e.polarity);
    const double t = e.t_ns * 1e-9;
    const size_t i = static_cast<size_t>(t * 1000);  // ground truth at 1 kHz
    if (i + 1 >= gt.size())
      continue;
    const double w = t * 1000 - i;
    // The square's sides at the event's time (linear between the two samples), nearest side.
    const Eigen::Vector2d p = cam.undistortedPixelLut(e.x, e.y).cast<double>();
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    ProjectedSegment sides[4];
    for (int s = 0; s < 4; ++s)
    {
      auto at = [&](const Eigen::Vector3d& pw) {
        return Eigen::Vector2d((1 - w) * k.project(gt[i].T_world_camera.toCamera(pw)) + w * k.project(gt[i + 1].T_world_camera.toCamera(pw)));
      };
      sides[s].set(at(map.segments[s].p0_world), at(map.segments[s].p1_world));
      centre += sides[s].a / 4;
    }
    int best = -1;
    double best_d = 1.5;
    for (int s = 0; s < 4; ++s)
      if (sides[s].parallelDistance(p) < -3 && sides[s].orthogonalDistance(p) < best_d)
      {
        best_d = sides[s].orthogonalDistance(p);
        best = s;
      }
    if (best < 0)
      continue;
    // Signed distance of the pixel centre from the edge towards the bright side (outside).
    const ProjectedSegment& side = sides[best];
    const double outside = side.normal.dot(centre - side.a) > 0 ? -1.0 : 1.0;
    const double d = outside * side.normal.dot(p - side.a);
    sq_centre += d * d;
    sq_run += (d + run_offset) * (d + run_offset);
    sq_constant += (d + constant_offset) * (d + constant_offset);
    ++n;
  }
  ASSERT_GT(n, 100000);
  const double rms_run = std::sqrt(sq_run / n), rms_constant = std::sqrt(sq_constant / n),
               rms_centre = std::sqrt(sq_centre / n);
  std::printf("edge position error per event: pixel centre %.3f px, constant offset %.3f px, run model %.3f px\n",
              rms_centre, rms_constant, rms_run);
  EXPECT_LT(rms_run, 0.15);       // measured 0.11 px
  EXPECT_GT(rms_constant, 0.22);  // measured 0.27 px
  EXPECT_GT(rms_centre, rms_constant);
}

// The contrast threshold is learned from the run lengths, for other sensors too.
TEST(EndToEnd, LearnsTheContrastThreshold)
{
  for (double threshold : {0.2, 0.3, 0.45})
  {
    const std::string t = std::to_string(threshold);
    const Simulated sim =
        simulate("flip", "duration: 0.8\nevents: {threshold_on: " + t + ", threshold_off: " + t + "}");
    LineTracker tracker(sim.config.camera, defaultSquareMap());
    runTracker(tracker, sim.output.events);
    EXPECT_NEAR(tracker.edgeModel().threshold(), threshold, 0.06 * threshold) << "simulated threshold " << threshold;
  }
}

TEST(Params, EdgeOffsetIsValidated)
{
  LineTrackerParams params;
  EXPECT_EQ(validateParams(params), "");
  params.edge_offset_px = -0.1;
  EXPECT_NE(validateParams(params).find("edge_offset_px"), std::string::npos);
  params.edge_offset_px = params.attribution.max_orthogonal_px;  // would move events out of range
  EXPECT_NE(validateParams(params).find("edge_offset_px"), std::string::npos);
  EXPECT_THROW(LineTracker(dvs_calibration::CameraModel::dvs128(), defaultSquareMap(), params), std::invalid_argument);
  params = LineTrackerParams();
  params.contrast_threshold = -0.1;
  EXPECT_NE(validateParams(params).find("contrast_threshold"), std::string::npos);
  params = LineTrackerParams();
  params.edge_contrast_ratio = 1.0;
  EXPECT_NE(validateParams(params).find("edge_contrast_ratio"), std::string::npos);
  params = LineTrackerParams();
  params.buffer_motion_px = -1;
  EXPECT_NE(validateParams(params).find("buffer_motion_px"), std::string::npos);
}

TEST(EndToEnd, FullSolverTracksLikeTheIncrementalOne)
{
  const Simulated sim = simulate("flip", "trajectory: {flip: {distance: 2.0}}\nduration: 0.6");
  LineTrackerParams params;
  params.estimator.solver = SolverType::kFullGaussNewton;
  LineTracker tracker(sim.config.camera, defaultSquareMap(), params);
  const TrackingRun run = runTracker(tracker, sim.output.events);
  ASSERT_FALSE(run.estimates.empty());
  const dvs_calibration::AccuracyReport r = dvs_calibration::evaluateTrajectory(run.estimates, sim.ground_truth, 0.05);
  EXPECT_EQ(r.samples_tracked, r.samples);
  EXPECT_LT(r.rms_position_m, 0.06);
  EXPECT_LT(r.rms_orientation_rad, 2.0 * kDeg);
}

TEST(Robustness, BackgroundNoise2HzPerPixel)
{
  const Simulated sim = simulate("flip", "events: {noise: {background_rate: 2.0}}");
  ASSERT_GT(sim.output.stats.noise_events, 40000u);  // 2 Hz x 16384 px x 1.5 s
  LineTracker tracker(sim.config.camera, defaultSquareMap());
  const TrackingRun run = runTracker(tracker, sim.output.events);
  ASSERT_FALSE(run.estimates.empty());
  EXPECT_LT(run.estimates.front().t - firstEventTime(sim.output.events), 0.25);
  // The progressive Hough alone gave the first pose 0.45 s after the first event here (noise
  // events explained by wrong segments no longer voted for the sides): the full Hough, tried in
  // the same attempt when the progressive one gives no pose, is what starts in time.
  EXPECT_GT(tracker.initializerStats().full_hough_attempts, 0u);
  EXPECT_LT(tracker.initializerStats().full_hough_attempts, tracker.initializerStats().attempts + 1);
  const dvs_calibration::AccuracyReport r = dvs_calibration::evaluateTrajectory(run.estimates, sim.ground_truth, 0.05);
  EXPECT_EQ(r.samples_fresh, r.samples);  // an estimate at every sample, never lost
  // Within 10 cm / 10 deg: 98.95 % measured (the noise's worst moments exceed 10 cm, issue 15).
  EXPECT_GT(r.trackedFraction(), 0.97);
  EXPECT_LT(r.rms_position_m, 0.06);  // measured 3.1 cm (2026-11-21; 6.9 cm before the edge model)
  EXPECT_LT(r.rms_orientation_rad, 3.0 * kDeg);
  // The initial pose is right (a polygon assembled from noise would be far off).
  EXPECT_LT(positionError(run.estimates.front().T_world_camera, sim.ground_truth[static_cast<size_t>(r.first_estimate_s * 1000)].T_world_camera), 0.15);
  EXPECT_EQ(run.final_state, TrackerState::kTracking);
}

TEST(Robustness, Flip2000DegPerSecond)
{
  const Simulated sim = simulate("flip", "trajectory: {flip: {peak_rate_deg_s: 2000}}");
  LineTracker tracker(sim.config.camera, defaultSquareMap());
  const TrackingRun run = runTracker(tracker, sim.output.events);
  ASSERT_FALSE(run.estimates.empty());
  const dvs_calibration::AccuracyReport r = dvs_calibration::evaluateTrajectory(run.estimates, sim.ground_truth, 0.05);
  EXPECT_EQ(r.samples_tracked, r.samples);
  EXPECT_LT(r.rms_position_m, 0.06);
  EXPECT_LT(r.max_position_m, 0.20);
  EXPECT_EQ(run.final_state, TrackerState::kTracking);
}

namespace
{
SyntheticEventParams idealDvs128()
{
  SyntheticEventParams p;
  p.k = PinholeK{115, 115, 63.5, 63.5};
  return p;
}

// The generator's events lie exactly on the edges (one per crossing of a pixel centre): no
// sub-pixel edge model, no offset.
LineTrackerParams idealSensorParams()
{
  LineTrackerParams p;
  p.edge_run_model = false;
  p.edge_offset_px = 0;
  return p;
}

}  // namespace

TEST(Robustness, OneEdgeOccludedFor100ms)
{
  // A slow roll with sideways drift; the left edge produces no events for 100 ms.
  const PoseFunction traj = [](double t) {
    return lookAt({-0.1 + 0.2 * t, 0.05 * std::sin(3 * t), 1.6}, {-0.1 + 0.2 * t, 0.05 * std::sin(3 * t), 0}, {0, 1, 0},
                  0.6 * std::sin(2.5 * t));
  };
  SyntheticEventParams p = idealDvs128();
  p.duration_s = 1.0;
  p.occluded_segment = 3;  // the map's left edge (x = -0.45)
  p.occlusion_start_s = 0.4;
  p.occlusion_end_s = 0.5;
  const SyntheticSequence seq = generateSyntheticEvents(defaultSquareMap(), traj, p);
  LineTracker tracker(idealCamera(), defaultSquareMap(), idealSensorParams());
  const TrackingRun run = runTracker(tracker, seq.events);
  ASSERT_FALSE(run.estimates.empty());
  dvs_calibration::Trajectory gt;
  for (const auto& g : seq.ground_truth)
    gt.push_back({g.t_s, g.pose});
  // During and after the occlusion the pose stays right: three edges carry the pose.
  // During the occlusion three edges carry the pose: it degrades (weakly observable lateral
  // translation) but the track holds; afterwards it is accurate again.
  const dvs_calibration::AccuracyReport during = dvs_calibration::evaluateTrajectory(run.estimates, gt, 0.05, 0.4, 0.5);
  EXPECT_EQ(during.samples_tracked, during.samples);
  EXPECT_LT(during.max_position_m, 0.20);
  EXPECT_EQ(run.stats.losses, 0u);
  const dvs_calibration::AccuracyReport after = dvs_calibration::evaluateTrajectory(run.estimates, gt, 0.05, 0.65, 1.0);
  EXPECT_LT(after.max_position_m, 0.03);
  EXPECT_EQ(run.final_state, TrackerState::kTracking);
}

TEST(Robustness, SquareLeavesTheViewAndComesBack)
{
  // Hovering on a small circle (0-0.5 s), the camera slides right until the square has left the
  // image entirely (1 s), comes back (1.5 s) and hovers again.
  const PoseFunction traj = [](double t) {
    const double slide = (t > 0.5 && t < 1.5) ? 1.6 * std::sin(M_PI * (t - 0.5)) : 0.0;
    const double x = slide + 0.08 * std::cos(8 * t), y = 0.08 * std::sin(8 * t);
    return lookAt({x, y, 1.6}, {x, y, 0}, {0, 1, 0}, 0.15 * std::sin(5 * t));
  };
  SyntheticEventParams p = idealDvs128();
  p.duration_s = 2.0;
  const SyntheticSequence seq = generateSyntheticEvents(defaultSquareMap(), traj, p);
  LineTracker tracker(idealCamera(), defaultSquareMap(), idealSensorParams());
  const TrackingRun run = runTracker(tracker, seq.events);
  dvs_calibration::Trajectory gt;
  for (const auto& g : seq.ground_truth)
    gt.push_back({g.t_s, g.pose});
  // Lost while out of view, with the reason; then found again.
  ASSERT_GE(run.stats.losses, 1u);
  EXPECT_NE(run.loss_reasons.front().find("left the view"), std::string::npos) << run.loss_reasons.front();
  EXPECT_GE(run.stats.reinitializations, 1u);
  EXPECT_EQ(run.final_state, TrackerState::kTracking);
  // Lost only after the square started to leave (0.5 s), and only while it was out.
  const double lost_at = std::find_if(run.transitions.begin(), run.transitions.end(), [](const auto& tr) {
                           return tr.second == TrackerState::kLost;
                         })->first;
  EXPECT_GT(lost_at, 0.55);
  EXPECT_LT(lost_at, 1.0);
  const dvs_calibration::AccuracyReport before = dvs_calibration::evaluateTrajectory(run.estimates, gt, 0.05, 0.0, 0.5);
  EXPECT_EQ(before.samples_tracked, before.samples);
  EXPECT_LT(before.max_position_m, 0.06);
  // (While the square re-enters, partial views can give false re-initialisations; the quality
  // monitor rejects them by attribution collapse: see README, known limitations.)
  // After the re-initialisation the pose is right again.
  const dvs_calibration::AccuracyReport after = dvs_calibration::evaluateTrajectory(run.estimates, gt, 0.05, 1.9, 2.0);
  EXPECT_GT(after.samples_tracked, 0);
  EXPECT_LT(after.max_position_m, 0.10);
}
