// Start and restart anywhere: end-to-end runs of the tracker on the sweep's scene classes
// (sweep_scene.h, simulated by the suite's software DVS), asserting the first-pose time after
// the map's edges start firing, no false initialisation, the tracked fraction and the accuracy
// against ground truth.
#include "reacquire_evaluation.h"
#include "sweep_evaluation.h"
#include "tracking_test_support.h"

#include <dvs_line_tracker/line_tracker.h>
#include <dvs_screen_sim/dataset.h>
#include <dvs_screen_sim/scene.h>
#include <dvs_screen_sim/sim_config.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <gtest/gtest.h>

namespace dvs_line_tracker
{
namespace
{
/// Scene `index` of the sweep (benchmark_init_sweep --scene index shows the same row).
SweepSceneSpec sweepScene(int index) { return sweepSceneSpecs(index + 1)[index]; }

/// `result` (optional) receives the run's figures.
void expectStartsAndTracks(const SweepSceneSpec& sp, double max_delay_s = 0.3, double min_tracked = 0.97,
                           double max_rms_ratio = 0.01, SweepResult* result = nullptr,
                           const LineTrackerParams& params = LineTrackerParams())
{
  const SweepScene scene = buildSweepScene(sp);
  const SweepResult r = runSweepScene(scene, params);
  if (result)
    *result = r;
  SCOPED_TRACE(sensorLabel(sp) + ", " + lensLabel(sp) + ", " + motionLabel(sp.motion) + ", " + mapLabel(sp.map) + ", " +
               noiseLabel(sp.noise) + (sp.partial ? ", partial" : "") + ", distance " + std::to_string(scene.distance));
  ASSERT_GE(r.edges_fire_s, 0.0) << "the scene's edges never fire: not a useful scene";
  ASSERT_GE(r.first_pose_s, 0.0) << "no pose at all";
  EXPECT_LE(r.first_pose_delay_s, max_delay_s);
  EXPECT_TRUE(r.first_pose_correct);
  EXPECT_EQ(r.false_initializations, 0);
  EXPECT_GE(r.tracked_fraction, min_tracked);
  EXPECT_LE(r.rms_position_ratio, max_rms_ratio);
}
}  // namespace

// Hand-held square 2 m from a 41 deg lens (128x128, contrast 3): two of its sides fire little in
// their middles and are detected as two collinear pieces each, 16 px apart; no polygon until
// the pieces were joined (joinCollinearSegments): first pose 0.80 s after the edges fire before,
// 0.06 s with the joins.
TEST(StartAnywhere, SideSeenAsTwoPiecesIsJoined) { expectStartsAndTracks(sweepScene(64), 0.3, 0.97, 0.025); }

// A square at 60 deg 0.65 m from a 109 deg lens (128x128, hand-held, contrast 3): its left side
// runs out of view at both ends, its near right side moves along itself and is not detected, and
// bottom and top run out of view. Only the closed polygon with the right side bridged between
// the inner ends of bottom and top fits (two more agreeing detections asked of it): first pose
// 0.58 s after the edges fire before, 0.08 s with it.
TEST(StartAnywhere, SteepSquareWithItsNearSideBridged) { expectStartsAndTracks(sweepScene(172), 0.3, 0.97, 0.025); }

// Close, wide and distorted (346x260, 98 deg, k1 -0.14, the square filling 89 % of the
// image height at 0.63 m), slow motion: no pose at all before the start-anywhere work.
TEST(StartAnywhere, CloseWideDistortedSlow) { expectStartsAndTracks(sweepScene(30)); }

// Far: 346x260 at 2.8 m (the square 29 % of the image height) seen 60 deg off its normal, hand-held.
TEST(StartAnywhere, FarSteepHandHeld) { expectStartsAndTracks(sweepScene(58)); }

// Slow on a 640x480 sensor, the square seen 60 deg off its normal from 1.7 m.
TEST(StartAnywhere, SlowVgaSteep) { expectStartsAndTracks(sweepScene(63)); }

// Far and nearly frontal (640x480, 44 deg, the square 19 % of the image height at 5 m, a corner
// out of view, slow): the corners' pose and its planar-PnP twin, tilted about 10 deg either side
// of the view axis, cover the sides about equally. The corners' pose, 20 deg off, was taken and
// confirmed (a false initialisation, 1.8 m off, tracked for the rest of the run); its twin, the
// true pose, lies 1.5-2 % closer to the refinement events and is now taken.
TEST(StartAnywhere, FarFrontalSquareTakesTheTwinCloserToTheEvents)
{
  expectStartsAndTracks(sweepScene(147), 0.3, 0.97, 0.03);
}

// Two identical squares: told apart by the whole map (the wrong one is not taken).
TEST(StartAnywhere, TwoSquares) { expectStartsAndTracks(sweepScene(31)); }

// A square and a triangle, heavy noise (2 Hz/px, 1 ms jitter, sigma_C 0.06).
TEST(StartAnywhere, SquareAndTriangleHeavyNoise) { expectStartsAndTracks(sweepScene(37)); }

// Partial view at the start: two squares on a 240x180 sensor, the view rolled and turned so
// that a corner of the right square lies outside the image, hand-held, low contrast.
TEST(StartAnywhere, CornerOutsideAtTheStart) { expectStartsAndTracks(sweepScene(1)); }

// A whole side out of view at the start: 240x180, 83 deg, k1 -0.23, the square filling 78 % of
// the image height at 0.93 m, hand-held: three sides and two corners in view (no pose at all
// before polygons with a side out of view were searched).
TEST(StartAnywhere, SideOutOfViewAtTheStart) { expectStartsAndTracks(sweepScene(25), 0.3, 0.97, 0.015); }

// Two squares whose top and bottom sides are collinear (one Hough segment each), a 2000 deg/s
// flip on a 128x128 sensor, low contrast: found once those segments are split where the
// squares' other sides meet them (no pose before). The flip at 1.45 m tracks at 3.8 % of the
// distance (the accuracy issue's class).
TEST(StartAnywhere, TwoSquaresWithCollinearSides) { expectStartsAndTracks(sweepScene(56), 0.3, 0.97, 0.06); }

// Two squares on a 346x260 sensor, 109 deg, the right square half out of view at the start,
// hand-held, low contrast: its top and bottom run out of view and its left side, moving along
// itself, is too weak to be detected; its corners are the inner ends of the top and bottom
// (bridged; no pose at all before).
TEST(StartAnywhere, UndetectedSideBetweenSidesOutOfView) { expectStartsAndTracks(sweepScene(46), 0.3, 0.97, 0.02); }

// Two squares in slow motion on a 128x128 sensor, 99 deg, at 1.5 m (26 % of the image height):
// the sides moving along themselves fire little, so most detections cover a side only 45-60 %
// of its length; such weak detections confirm a strongly covered one, and three agreeing ones
// start alone (no pose at all before weak detections were kept).
TEST(StartAnywhere, SlowPairWithWeakSides) { expectStartsAndTracks(sweepScene(12), 0.3, 0.97, 0.015); }

// Two squares with collinear sides at 2.6 m on a 240x180 sensor, 85 deg, k1 -0.25, low contrast,
// in the 0.1 s hover before a 2000 deg/s flip: the squares' polygons come from the split
// segments, found only when more than the first 8 polygons are searched, and their vertical
// sides, moving along themselves, fire so little that every detection is weak (covered 53-59 %);
// three agreeing weak detections start (no pose at all before). The flip at range tracks at
// 1.6 % of the distance (the accuracy issue's class).
TEST(StartAnywhere, WeakPairBeforeAFlip) { expectStartsAndTracks(sweepScene(41), 0.3, 0.97, 0.03); }

// A grey square (contrast 3) at 3.1 m on a 640x480 sensor, slow: a slow edge's neighbouring
// pixels fire 10-30 ms apart, longer than the Hough's background-activity filter looked back
// while its horizon scaled with sqrt(pixels) (the first pose came 1.2 s late and 5-10 % off);
// the horizon now holds the 128x128 sensor's events per pixel.
TEST(StartAnywhere, GreySquareSlowOnVga) { expectStartsAndTracks(sweepScene(39), 0.3, 0.97, 0.015); }

// Slow on a 640x480 sensor with realistic noise (61,000 noise events/s): where the roll sway
// turns, the edges stop firing and the attribution falls to chance; the events left are noise
// (2-3 % of them next to each other, against 40-90 % for a scene the pose does not explain),
// so the track is kept (it was lost there, 80.8 % tracked, though 0.7 % of the distance off).
TEST(StartAnywhere, KeepsTheTrackWhenTheCameraPauses)
{
  SweepResult r;
  expectStartsAndTracks(sweepScene(15), 0.3, 0.99, 0.01, &r);
  EXPECT_EQ(r.losses, 0) << r.last_loss_reason;
}

// A grey square (contrast 3) slow at 1.18 m, 81 % of a 346x260 image through a 66 deg lens,
// one side out of view throughout: 5,000-20,000 attributed events per second. The partial-view
// damping, a prior per event, held the pose so hard at that rate that the weakly observable pair
// (lateral translation / tilt) trailed the motion, 5 cm / 2 deg behind at 1.2 s (2.6 % of the
// distance); scaled with the event rate (damping_partial_view_rate) the pose follows: 1.4 %.
TEST(StartAnywhere, SlowPartialViewFollowsTheCamera)
{
  SweepResult r;
  expectStartsAndTracks(sweepScene(54), 0.3, 0.99, 0.018, &r);
  LineTrackerParams per_event;
  per_event.damping_partial_view_rate = 0;
  const SweepResult held = runSweepScene(buildSweepScene(sweepScene(54)), per_event);
  EXPECT_GT(held.rms_position_ratio, 1.5 * r.rms_position_ratio)
      << "the damping per event, not per time, should trail the motion";
}

// Two grey squares (contrast 3) hand-held at 0.91 m through a 106 deg lens on 128x128 (scene 76
// of a 128-scene sweep, beyond the 64 tuned on): one whole square was taken for the other, the
// other then projected beyond the image where no side needed covering, and the start was 118 cm
// off; every pose of a several-polygon map must now explain half the window's events.
TEST(StartAnywhere, PairNotTakenForTheOtherSquare) { expectStartsAndTracks(sweepScene(76), 0.35, 0.97, 0.02); }

// A square tilted 60 deg, 0.60 m from a 97 deg lens on 346x260 (k1 -0.03), slow, part of it out
// of view (scene 78): its far corners turn by 33-34 deg, outside the usual 45-135 deg bounds,
// so no pose at all before the wide-turn pass (polygon_wide_min/max_angle_deg).
TEST(StartAnywhere, SteepSquareCloseToAWideLens)
{
  expectStartsAndTracks(sweepScene(78));
  // Without the wide-turn pass: no pose at all.
  LineTrackerParams usual_only;
  usual_only.polygon_wide_min_angle_deg = usual_only.polygon.min_turn_angle_deg;
  usual_only.polygon_wide_max_angle_deg = usual_only.polygon.max_turn_angle_deg;
  EXPECT_LT(runSweepScene(buildSweepScene(sweepScene(78)), usual_only).first_pose_s, 0.0);
}

// A square tilted 60 deg, 5 m from a 48 deg lens on 240x180, in a 2000 deg/s flip under heavy
// noise (scene 161): the flip's smear and the noise make blobs in which small quadrilaterals of
// noise segments are covered on every side (two false starts, 84 % of the distance off). The
// strips beside their sides are as busy as the sides (init_max_surrounding_coverage): no start
// rather than a false one. The false starts came with the thesis's attribution up to 10 px
// beyond a segment's end, which the initial refinement used too (since the twenty-ninth session
// 2 px: then the scene no longer starts falsely even without the check).
TEST(StartAnywhere, NoStartFromAPolygonDrawnInABlobOfEvents)
{
  const SweepScene scene = buildSweepScene(sweepScene(161));
  EXPECT_EQ(runSweepScene(scene, LineTrackerParams()).false_initializations, 0);
  LineTrackerParams unlimited;
  unlimited.attribution.max_parallel_px = 10.0;
  EXPECT_EQ(runSweepScene(scene, unlimited).false_initializations, 0);
  unlimited.init_max_surrounding_coverage = 1.0;
  EXPECT_GT(runSweepScene(scene, unlimited).false_initializations, 0);
}

// A still DVS128 2 m in front of a 5 x 7 grid of discs (0.14 m, 0.22 m apart) blinking at 15 Hz,
// pitched 30 deg (the screen loop's alignment grid, seen by the tracker while the screen is
// aligned): the grid's rows and diagonals make parallelograms that fit the 0.9 m square seen
// 77 deg off its normal, 2 m off (seeds 1 and 2; explaining 0.27-0.31 of the Hough window). No
// square is there: no start (init_min_explained and init_max_view_angle_deg; with the real
// screen loop's grid under load a start 2.5 m off lasted into the playback: CI's failed
// screen_sim.test).
TEST(StartAnywhere, NoStartOnABlinkingDotGrid)
{
  for (const int seed : {1, 2})
  {
    SCOPED_TRACE("seed " + std::to_string(seed));
    dvs_screen_sim::SimConfig config = dvs_screen_sim::resolveSimConfig(
        "linear", YAML::Load("{seed: " + std::to_string(seed) +
                             ", duration: 1.5, trajectory: {linear: {start_position: [0, 0, 2], end_position: [0, 0, "
                             "2], start_ypr_deg: [0, -30, 4], end_ypr_deg: [0, -30, 4], duration: 1.5}}}"));
    dvs_screen_sim::Scene grid = dvs_screen_sim::circleGridScene(5, 7, 0.22, 0.14, 0.9, 0.1);
    for (auto& disc : grid.polygons)
    {
      disc.modulation.type = dvs_screen_sim::IntensityModulation::Type::Square;
      disc.modulation.frequency_hz = 15.0;
      disc.modulation.low = 0.1;
      disc.modulation.high = 0.9;
    }
    grid.finalize();
    config.scene = grid;
    const dvs_screen_sim::SimulationOutput sim = dvs_screen_sim::runSimulation(config);
    ASSERT_GT(sim.events.size(), 50000u) << "the grid does not blink";
    LineTracker checked(config.camera, defaultSquareMap(), LineTrackerParams());
    EXPECT_EQ(runTracker(checked, sim.events).stats.initializations, 0u);
    LineTrackerParams unchecked;
    unchecked.init_min_explained = 0.0;
    unchecked.init_max_view_angle_deg = 90.0;
    LineTracker fooled(config.camera, defaultSquareMap(), unchecked);
    const TrackingRun r = runTracker(fooled, sim.events);
    ASSERT_GE(r.stats.initializations, 1u) << "without the checks the grid no longer fools the initialiser: not a useful scene";
    ASSERT_FALSE(r.estimates.empty());
    const Eigen::Vector3d p_true = sim.groundtruth.front().T_world_camera.p_world_camera();
    EXPECT_GT((r.estimates.front().T_world_camera.p_world_camera() - p_true).norm(), 1.0);
  }
}

// The initialiser attributes the Hough window's events (spread over the window's time) at the
// Hough's distance, whatever the tracker's attribution distance for single events: a tighter
// max_orthogonal_distance_px changes nothing before the first pose (scene 76, a pair of squares).
TEST(StartAnywhere, InitialisationIgnoresTheTrackersAttributionDistance)
{
  const SweepScene scene = buildSweepScene(sweepScene(76));
  const SweepResult usual = runSweepScene(scene, LineTrackerParams());
  LineTrackerParams tight;
  tight.attribution.max_orthogonal_px = 1.5;
  const SweepResult r = runSweepScene(scene, tight);
  ASSERT_GT(usual.first_pose_s, 0.0);
  EXPECT_EQ(r.first_pose_s, usual.first_pose_s);
  EXPECT_TRUE(r.first_pose_correct);
  EXPECT_EQ(r.init_stats.attempts, usual.init_stats.attempts);
  EXPECT_EQ(r.init_stats.polygons, usual.init_stats.polygons);
}

// A grey square tilted 60 deg at 0.96 m on 640x480 (78 deg, k1 -0.17), a corner 260 px below the
// image before a 2000 deg/s flip (scene 107): the two sides meeting there run out of view
// 210 px apart, too far from their corner for the gap rule (no pose at all before). Its first
// pose comes 0.285 s after the edges fire (so a bound of 0.35 s).
TEST(StartAnywhere, CornerFarBelowTheImage) { expectStartsAndTracks(sweepScene(107), 0.35, 0.97, 0.01); }

// A grey square at 0.55 m on 128x128 (85 deg, k1 -0.25) rolling through 2000 deg/s flips
// (scene 104): re-acquisitions mid-roll, where the square is upside down or on its side, took
// one of its other rotations (88 deg off, twice); the map's up picks its rotation only while
// the confirming detections roll slower than init_max_roll_rate. Without the partial-view
// hold (below) the track is lost mid-roll and re-acquired there: 72 % tracked.
TEST(StartAnywhere, NoWrongRotationWhileRolling)
{
  LineTrackerParams params;
  params.partial_view_grace_s = 0;
  SweepResult r;
  expectStartsAndTracks(sweepScene(104), 0.3, 0.65, 0.025, &r, params);
  EXPECT_GE(r.initializations, 2) << "no re-acquisition mid-roll: the test no longer tests what it says";
  EXPECT_EQ(r.partial_views_held, 0u) << "a partial view held without a grace";
}

// The same scene by default: mid-flip only two sides of the square are in view for about
// 30 ms; held through it (partial_view_grace_s, 50 ms), the track goes on instead of needing
// 0.25 s to start again (96.6 % tracked against 71.6 %).
TEST(StartAnywhere, ABriefCornerViewMidFlipIsHeld)
{
  SweepResult r;
  expectStartsAndTracks(sweepScene(104), 0.3, 0.95, 0.02, &r);
  EXPECT_EQ(r.initializations, 1);
  // Counted (the nodelet's diagnostics show these): every hold resumed, none longer than the
  // grace (plus a quality check interval's events).
  EXPECT_GE(r.partial_views_held, 1u);
  EXPECT_EQ(r.partial_views_resumed, r.partial_views_held);
  EXPECT_GT(r.partial_view_held_s, 0.0);
  EXPECT_LE(r.partial_view_held_s, r.partial_views_held * (LineTrackerParams().partial_view_grace_s + 0.01));
}

// A steep grey square 0.6 m away (scene 157) turns until only two sides are in view for 0.15 s,
// longer than the hold: the hold ends in a loss (counted as held, not resumed), and the track is
// re-acquired once three sides are back.
TEST(StartAnywhere, APartialViewLongerThanTheGraceIsALoss)
{
  const SweepResult r = runSweepScene(buildSweepScene(sweepScene(157)));
  EXPECT_GE(r.partial_views_held, 1u);
  EXPECT_LT(r.partial_views_resumed, r.partial_views_held);
  EXPECT_GE(r.losses, 1);
  EXPECT_GE(r.initializations, 2);
  EXPECT_EQ(r.false_initializations, 0);
}

// A square and a triangle in a 2000 deg/s flip on 128x128, 109 deg (scene 92): the roll lagging
// in the Hough window made the up pick the triangle rotated by 120 deg, the square then placed
// out of view (197 % of the distance off); the rotation that also explains the square's
// events now wins, whatever the up says.
TEST(StartAnywhere, RotationChosenByTheRestOfTheMap) { expectStartsAndTracks(sweepScene(92), 0.3, 0.97, 0.025); }

// Two squares side by side look the same turned by 180 deg (scene 105: 240x180, slow, heavy
// noise): the events cannot tell the two apart, so the map's up picks between them.
TEST(StartAnywhere, SymmetricPairIsTakenUpright) { expectStartsAndTracks(sweepScene(105)); }

// A 0.4 s blackout of every event in the middle of a hand-held motion (the camera moves about
// 0.16 m and turns meanwhile): the stale pose is dropped and a correct pose (5 % / 3 deg) is
// back within 0.3 s after the events return.
TEST(StartAnywhere, ReacquiresAfterBlackout)
{
  const SweepScene scene = buildSweepScene(sweepScene(40));
  dvs_driver::EventVector events = simulateSweepScene(scene);
  const int64_t begin = 600000000, end = 1000000000;
  events.erase(std::remove_if(events.begin(), events.end(),
                              [&](const dvs_driver::Event& e) { return e.t_ns >= begin && e.t_ns < end; }),
               events.end());
  LineTracker tracker(scene.camera, scene.map);
  double first = -1, back = -1;
  for (const auto& e : events)
  {
    if (!tracker.processEvent(e))
      continue;
    const double t = e.t_ns * 1e-9;
    first = first < 0 ? t : first;
    const dvs_calibration::Pose truth = scene.trajectory->poseAt(t);
    const double dist = (truth.p_world_camera() - scene.target).norm();
    if (e.t_ns >= end && back < 0 && positionError(truth, tracker.pose()) <= 0.05 * dist &&
        orientationError(truth, tracker.pose()) <= 3 * M_PI / 180)
      back = t - end * 1e-9;
  }
  ASSERT_GE(first, 0.0);
  EXPECT_LT(first, begin * 1e-9);
  EXPECT_EQ(tracker.stats().losses, 1u);
  EXPECT_NE(tracker.lastLossReason().find("no events for"), std::string::npos) << tracker.lastLossReason();
  ASSERT_GE(back, 0.0) << "never re-acquired";
  EXPECT_LE(back, 0.3);
}

// --- Re-acquisition after a disturbance (benchmark_reacquire's scenes) ---

/// Re-acquisition scene `index` run with `params`: a correct pose back within 0.3 s of the map's
/// edges firing again, no false re-initialisation, and the track held from 0.3 s after that.
/// Returns the run's result.
ReacquireResult expectReacquires(int index, const LineTrackerParams& params = LineTrackerParams())
{
  const ReacquireResult r = runReacquireScene(buildReacquireScene(sweepScene(index)), index, params);
  SCOPED_TRACE("scene " + std::to_string(index) + ", last loss: " + r.last_loss_reason);
  // (Fatal failures as ASSERT_* would have them, in a function that returns a value.)
  if (!r.tracking_before)
    ADD_FAILURE() << "not tracking when the disturbance began: not a useful scene";
  else if (r.edges_refire_s < 0)
    ADD_FAILURE() << "the map never fires again: not a useful scene";
  else if (r.back_after_s < 0)
    ADD_FAILURE() << "no correct pose after the disturbance";
  if (!r.tracking_before || r.edges_refire_s < 0 || r.back_after_s < 0)
    return r;
  EXPECT_LE(r.back_after_s, 0.3);
  EXPECT_EQ(r.false_reinitializations, 0);
  EXPECT_GE(r.tracked_after, 0.97);
  return r;
}

// The disturbances do what they say: a blackout removes every event of its span and nothing
// else, an occlusion only the events on its side of the line, a bump turns the camera by its
// angle within 20 ms and keeps it there, and a camera leaving the view has no map in view while
// it is turned away and all of it back afterwards.
TEST(Reacquire, DisturbancesAreWhatTheySay)
{
  for (int index : {0, 1, 2, 3})
  {
    const SweepScene scene = buildReacquireScene(sweepScene(index));
    const DisturbedScene d = disturbSweepScene(scene, index);
    const Disturbance& dist = d.disturbance;
    SCOPED_TRACE(disturbanceLabel(dist.kind));
    ASSERT_EQ(static_cast<int>(dist.kind), index % 4);
    const int64_t from = std::llround(dist.start_s * 1e9), to = std::llround((dist.start_s + dist.length_s) * 1e9);
    const dvs_driver::EventVector all = simulateSweepScene(d.scene);
    size_t in_span = 0, hidden_side = 0;
    for (const auto& e : d.events)
      if (e.t_ns >= from && e.t_ns < to)
      {
        ++in_span;
        hidden_side += dist.occluder_normal.dot(Eigen::Vector2d(e.x, e.y) - dist.occluder_point) > 0 ? 1 : 0;
      }
    const dvs_calibration::Pose base = scene.trajectory->poseAt(dist.start_s + 0.05);
    const dvs_calibration::Pose turned = d.scene.trajectory->poseAt(dist.start_s + 0.05);
    switch (dist.kind)
    {
      case DisturbanceKind::kBlackout:
        EXPECT_EQ(in_span, 0u);
        EXPECT_GT(all.size(), d.events.size());
        EXPECT_NEAR(orientationError(base, turned), 0.0, 1e-12);
        break;
      case DisturbanceKind::kOcclusion:
        EXPECT_GT(in_span, 0u);
        EXPECT_EQ(hidden_side, 0u);
        EXPECT_GT(all.size(), d.events.size());
        break;
      case DisturbanceKind::kBump:
        EXPECT_EQ(all.size(), d.events.size());
        EXPECT_NEAR(orientationError(base, turned) * 180 / M_PI, dist.angle_deg, 1e-6);
        EXPECT_NEAR(positionError(base, turned), 0.0, 1e-12);
        EXPECT_NEAR(orientationError(scene.trajectory->poseAt(dist.start_s - 0.001),
                                     d.scene.trajectory->poseAt(dist.start_s - 0.001)),
                    0.0, 1e-12);
        break;
      case DisturbanceKind::kLeaveView:
        EXPECT_EQ(all.size(), d.events.size());
        EXPECT_EQ(visibleEdges(d.scene, d.scene.trajectory->poseAt(dist.start_s + 0.15 + 0.5 * dist.length_s)), 0);
        EXPECT_NEAR(orientationError(scene.trajectory->poseAt(dist.backAt()), d.scene.trajectory->poseAt(dist.backAt())),
                    0.0, 1e-9);
        break;
    }
  }
}

// A large square hand-held at 0.93 m (240x180, 83 deg lens), half of it occluded for 0.58 s:
// the buffers of the hidden sides held the pose still while the camera turned on, and after the
// occlusion the track sat 10-30 px off the edges with 15-25 % of the events still near its
// lines (above the 2 % collapse), for the rest of the run (RMS 96 % of the distance). The share
// dropping far below the track's own level (76 %) with the rest structure is now a loss.
TEST(Reacquire, SlipAfterAnOcclusionIsALoss) { expectReacquires(25); }

// Two grey squares hand-held at 0.91 m through a 106 deg lens (128x128), a 0.6 s blackout: the
// re-initialisation took the right square for the left one (1.2 m off), the left one then out of
// view; the true hypothesis, which puts both in view, was rejected because the left square's
// sides along the motion had not fired yet, though it explained clearly more of the events.
TEST(Reacquire, PairReacquiredAsTheRightSquare) { expectReacquires(76); }

// Two grey squares hand-held at 0.85 m through a 110 deg lens (240x180), one of them occluded
// for 0.87 s: the track was lost, and the square in view was re-initialised as the other one
// (1.2 m off), which put the occluded square out of view; the hypothesis that the track had
// been following lay much closer to the pose before the loss, and now makes it wait.
TEST(Reacquire, PairDuringAnOcclusionWaitsForTheSquareThePriorSaw) { expectReacquires(61); }

// A square at 60 deg in a 2000 deg/s flip at 1.17 m (346x260, 106 deg lens, heavy noise), bumped
// by 14 deg: the estimate settled on a pose that fits two sides and puts the other two where no
// edge is, the real ones firing inside the projected square (21 % of the distance off for the
// rest of the run, never lost). A side that moves across the image without events while its
// polygon's other sides fire and unexplained structure arrives near it is now a loss
// (silent_side_check.h); the track is back 0.12 s after the edges fire again. (Since the solve
// waits for events off their lines, solve_min_offset_px, the default keeps the track through
// this bump; the slip is reproduced with every event solved.)
TEST(Reacquire, APoseThatPutsASideWhereNoEdgeIsIsALoss)
{
  LineTrackerParams every_event;
  every_event.solve_min_offset_px = 0;
  const ReacquireResult r = expectReacquires(14, every_event);
  EXPECT_NE(r.last_loss_reason.find("no edge is where the pose puts it"), std::string::npos) << r.last_loss_reason;
  expectReacquires(14);
}

// Half the image occluded for 0.69 s over a square and a triangle hand-held at 1.01 m (240x180,
// 100 deg lens, grey): the hidden sides move across the image without events too, but their
// edges fire nowhere in view, so the track goes on through the occlusion.
TEST(Reacquire, AnOccludedSideKeepsTheTrack)
{
  const ReacquireResult r = runReacquireScene(buildReacquireScene(sweepScene(13)), 13, LineTrackerParams());
  ASSERT_TRUE(r.tracking_before);
  EXPECT_TRUE(r.kept) << r.last_loss_reason;
  EXPECT_GE(r.back_after_s, 0.0);
  EXPECT_LE(r.back_after_s, 0.05);
  EXPECT_GE(r.tracked_after, 0.97);
}

// A 0.51 s blackout while hand-held (128x128, scene 112): the camera moved further than the
// Hough's attribution distance meanwhile. The prior refined from its capture range
// (reacquire_capture_px) covers the map's sides again and confirms the first detection: the
// track is back 0.017 s after the edges fire again. Refined at the Hough's distance only, the
// prior never covers them, and a second detection confirms the first: 0.049 s.
TEST(Reacquire, ThePriorCapturesACameraThatMovedDuringABlackout)
{
  const ReacquireResult captured = expectReacquires(112);
  LineTrackerParams no_capture;
  no_capture.reacquire_capture_px = 0;
  const ReacquireResult fine = runReacquireScene(buildReacquireScene(sweepScene(112)), 112, no_capture);
  ASSERT_GE(fine.back_after_s, 0.0);
  EXPECT_EQ(fine.false_reinitializations, 0);
  EXPECT_LT(captured.back_after_s + 0.01, fine.back_after_s);
  EXPECT_LT(captured.init_stats.attempts, fine.init_stats.attempts);
}

// Blackout, occlusion, bump and the map leaving the view, on scenes of each motion class.
TEST(Reacquire, AfterABlackout) { expectReacquires(4); }
TEST(Reacquire, AfterAnOcclusion) { expectReacquires(9); }
TEST(Reacquire, AfterABump) { expectReacquires(6); }
TEST(Reacquire, AfterLeavingTheView) { expectReacquires(15); }
}  // namespace dvs_line_tracker
