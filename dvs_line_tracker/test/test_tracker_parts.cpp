// The tracker's parts on their own: the parameter table, the updater, the loss monitor, the
// propagator seam, and a reset that reaches every part.
#include "synthetic_events.h"

#include <dvs_line_tracker/event_updater.h>
#include <dvs_line_tracker/line_tracker.h>
#include <dvs_line_tracker/loss_monitor.h>
#include <dvs_line_tracker/tracker_initializer.h>
#include <dvs_line_tracker/tracker_params.h>

#include <gtest/gtest.h>
#include <algorithm>
#include <memory>

#include <random>

#include <fstream>
#include <limits>
#include <sstream>

using namespace dvs_line_tracker;

namespace
{
TrackingGeometry dvs128Geometry()
{
  const auto cam = dvs_calibration::CameraModel::dvs128();
  TrackingGeometry g;
  g.map = defaultSquareMap();
  g.k = {cam.intrinsics().fx, cam.intrinsics().fy, cam.intrinsics().cx, cam.intrinsics().cy};
  g.width = cam.width();
  g.height = cam.height();
  return g;
}

const Pose kFront = lookAt({0.05, -0.02, 1.6}, {0, 0, 0}, {0, 1, 0}, 0.1);

// A slow roll with sideways drift the tracker initialises on (ideal events on the edges).
SyntheticSequence slowRoll(double duration_s)
{
  SyntheticEventParams p;
  p.k = PinholeK{115, 115, 63.5, 63.5};
  p.duration_s = duration_s;
  return generateSyntheticEvents(
      defaultSquareMap(),
      [](double t) {
        return lookAt({-0.1 + 0.2 * t, 0.05 * std::sin(3 * t), 1.6}, {-0.1 + 0.2 * t, 0.05 * std::sin(3 * t), 0},
                      {0, 1, 0}, 0.6 * std::sin(2.5 * t));
      },
      p);
}

}  // namespace

TEST(TrackerParams, TableNamesTheBadParameterAndItsBounds)
{
  LineTrackerParams p;
  EXPECT_EQ(validateParams(p), "");
  p.buffer_size = 1;
  p.hough.radius_bin_px = 1e-9;  // used to be a vector-too-large error deep inside the Hough space
  p.min_unattributed_structure = 1.5;
  p.init_min_up_margin = -0.1;
  p.init_max_roll_rate_deg_s = 0;
  p.init_max_surrounding_coverage = 1.5;
  p.init_min_explained = -1;
  p.init_max_view_angle_deg = 120;
  p.attribution_drop_ratio = -0.1;
  p.loss_neighbour_events = 0;
  p.loss_silent_side_ratio = 1.5;
  p.solve_min_offset_px = -0.1;
  p.reacquire_capture_px = -1;
  p.damping_partial_view_rate = -5;
  const std::string err = validateParams(p);
  EXPECT_NE(err.find("buffer_size must be in [2, 1024] events (got 1)"), std::string::npos) << err;
  EXPECT_NE(err.find("hough_radius_bin_px must be in [0.1, 100] px"), std::string::npos) << err;
  EXPECT_NE(err.find("min_unattributed_structure must be in [0, 1]"), std::string::npos) << err;
  EXPECT_NE(err.find("init_min_up_margin must be in [0, 2]"), std::string::npos) << err;
  EXPECT_NE(err.find("init_max_roll_rate must be"), std::string::npos) << err;
  EXPECT_NE(err.find("init_max_surrounding_coverage must be in [0, 1] (got 1.5)"), std::string::npos) << err;
  EXPECT_NE(err.find("init_min_explained must be in [0, 1] (got -1)"), std::string::npos) << err;
  EXPECT_NE(err.find("init_max_view_angle_deg must be in [0, 90] deg (got 120)"), std::string::npos) << err;
  EXPECT_NE(err.find("attribution_drop_ratio must be in [0, 1] (got -0.1)"), std::string::npos) << err;
  EXPECT_NE(err.find("loss_neighbour_events must be in [1, 1e+07] events (got 0)"), std::string::npos) << err;
  EXPECT_NE(err.find("loss_silent_side_ratio must be in [0, 1] (got 1.5)"), std::string::npos) << err;
  EXPECT_NE(err.find("solve_min_offset_px must be >= 0 px (got -0.1)"), std::string::npos) << err;
  EXPECT_NE(err.find("reacquire_capture_px must be in [0, 1000] px (got -1)"), std::string::npos) << err;
  EXPECT_NE(err.find("damping_partial_view_rate must be in [0, 1e+09] events/s (got -5)"), std::string::npos) << err;
  EXPECT_THROW(LineTracker(dvs_calibration::CameraModel::dvs128(), defaultSquareMap(), p), std::invalid_argument);
}

TEST(PoseTypes, RollRateIsTheTurnAboutTheOpticalAxis)
{
  using dvs_calibration::lookAt;
  const Eigen::Vector3d eye(0.3, -0.2, 1.5), target(0, 0, 0), up(0, 1, 0);
  const Pose a = lookAt(eye, target, up, 0.1);
  // 10 deg of roll in 10 ms: 1000 deg/s, signed.
  EXPECT_NEAR(rollRateDegS(a, lookAt(eye, target, up, 0.1 + 10 * M_PI / 180), 0.01), 1000, 1e-6);
  EXPECT_NEAR(rollRateDegS(a, lookAt(eye, target, up, 0.1 - 10 * M_PI / 180), 0.01), -1000, 1e-6);
  // Panning (about the camera's y axis) is no roll.
  const Pose panned = Pose::fromWorldCamera(Eigen::Matrix3d(a.R_world_camera() * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY())),
                                            a.p_world_camera());
  EXPECT_NEAR(rollRateDegS(a, panned, 0.01), 0, 1e-9);
}

TEST(PoseTypes, AnIncrementTurnsByItsRotationVector)
{
  // Small increments (the per-event steps) take a formula of their own: each must be the
  // rotation exp([w]x) to third order in |w|, orthonormal to rounding, and move the camera
  // centre as T_camera_world' = (dR, dt) * T_camera_world says.
  using dvs_calibration::lookAt;
  const Pose start = lookAt(Eigen::Vector3d(0.3, -0.2, 1.5), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), 0.1);
  for (const double size : {1e-6, 1e-4, 3e-3, 9e-3, 0.05, 0.5})
  {
    Vector6d delta;
    delta << 0.6 * size, -0.48 * size, 0.64 * size, 0.01, -0.02, 0.03;
    Pose p = start;
    p.applyCameraIncrement(delta);
    const Eigen::Matrix3d dR = Eigen::AngleAxisd(size, delta.head<3>().normalized()).toRotationMatrix();
    const double third_order = size * size * size;
    EXPECT_LT((p.R_camera_world - dR * start.R_camera_world).norm(), third_order + 1e-15) << "|w| " << size;
    EXPECT_LT((p.R_camera_world * p.R_camera_world.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_NEAR(p.R_camera_world.determinant(), 1.0, 1e-14);
    EXPECT_LT((p.t_camera_world - (p.R_camera_world * start.R_world_camera() * start.t_camera_world + delta.tail<3>())).norm(),
              1e-14);
  }
}

TEST(TrackerParams, CrossParameterRules)
{
  LineTrackerParams p;
  p.polygon.min_turn_angle_deg = 120;
  p.polygon.max_turn_angle_deg = 100;
  EXPECT_NE(validateParams(p).find("polygon_min_angle_deg must be < polygon_max_angle_deg"), std::string::npos);
  // The wide turn bounds must contain the usual ones (equal: the wide pass is off).
  LineTrackerParams w;
  EXPECT_EQ(validateParams(w), "");
  w.polygon_wide_min_angle_deg = 50;
  EXPECT_NE(validateParams(w).find("polygon_wide_min_angle_deg must be <= polygon_min_angle_deg"), std::string::npos);
  w.polygon_wide_min_angle_deg = w.polygon.min_turn_angle_deg;
  w.polygon_wide_max_angle_deg = w.polygon.max_turn_angle_deg;
  EXPECT_EQ(validateParams(w), "");
}

TEST(TrackerParams, YamlUsesTheTableAndTheSolverName)
{
  const std::string path = testing::TempDir() + "tracker_params_test.yaml";
  std::ofstream(path) << "buffer_size: 12\nsolver: full\ndamping: 0.5\nhough_remove_found_votes: false\n"
                          "init_full_hough_fallback: false\n";
  LineTrackerParams p;
  loadTrackerParamsYaml(path, p);
  EXPECT_EQ(p.buffer_size, 12);
  EXPECT_FALSE(p.hough.remove_found_votes);
  EXPECT_FALSE(p.init_full_hough_fallback);
  EXPECT_EQ(p.estimator.solver, SolverType::kFullGaussNewton);
  EXPECT_DOUBLE_EQ(p.estimator.damping, 0.5);
  std::ofstream(path) << "solver: fastest\n";
  EXPECT_THROW(loadTrackerParamsYaml(path, p), std::runtime_error);
  std::ofstream(path) << "bufer_size: 12\n";
  try
  {
    loadTrackerParamsYaml(path, p);
    FAIL() << "misspelt name accepted";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("unknown parameter 'bufer_size'"), std::string::npos) << e.what();
  }
}

TEST(TrackerParams, ReadmeTableListsEveryParameter)
{
  std::ifstream in(TRACKER_README);
  ASSERT_TRUE(in) << TRACKER_README;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string readme = ss.str();
  // The README holds the tables exactly as the code prints them (track_offline --list-params).
  LineTrackerParams p;
  std::string solver = solverTypeName(p.estimator.solver);
  TrackerNodeSettings node;
  EXPECT_NE(readme.find(trackerParamTable(p, solver).markdownTable()), std::string::npos)
      << "README.md's tracker parameter table differs from `track_offline --list-params`";
  EXPECT_NE(readme.find(nodeParamTable(node).markdownTable()), std::string::npos)
      << "README.md's node parameter table differs from `track_offline --list-params`";
}

TEST(EventUpdater, PartialViewDampingFallsWithTheEventRateBelowItsRate)
{
  const TrackingGeometry g = dvs128Geometry();
  LineTrackerParams params;
  params.estimator.damping = 0.07;
  params.damping_partial_view = 1.0;
  params.damping_partial_view_rate = 30000;
  const EventUpdater updater(g, params);
  EXPECT_DOUBLE_EQ(updater.partialViewDamping(-1), 1.0) << "rate not known: the full damping";
  EXPECT_DOUBLE_EQ(updater.partialViewDamping(1e6), 1.0);
  EXPECT_DOUBLE_EQ(updater.partialViewDamping(30000), 1.0);
  EXPECT_NEAR(updater.partialViewDamping(15000), 0.07 + 0.93 * 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(updater.partialViewDamping(0), 0.07) << "no event: down to the usual damping";
  params.damping_partial_view_rate = 0;
  EXPECT_DOUBLE_EQ(EventUpdater(g, params).partialViewDamping(100), 1.0) << "off";
  // A partial-view damping below the usual one: the usual one.
  params.damping_partial_view = 0.01;
  params.damping_partial_view_rate = 30000;
  EXPECT_DOUBLE_EQ(EventUpdater(g, params).partialViewDamping(15000), 0.07);
}

TEST(EventUpdater, StartsSeedsAndUpdatesOnAttributedEventsOnly)
{
  const TrackingGeometry g = dvs128Geometry();
  LineTrackerParams params;
  EstimatorState state;
  state.resize(g.map.segments.size(), params.buffer_size);
  EventUpdater updater(g, params);
  EXPECT_EQ(updater.start(state, kFront), 4);
  for (const auto& b : state.buffers)
    EXPECT_EQ(b.size(), params.buffer_size);
  // An event on the first side, 0.8 px off it along its normal: attributed, the pose moves.
  const ProjectedSegment& s = state.projected[0];
  const Eigen::Vector2d on_side = 0.5 * (s.a + s.b) + 0.8 * s.normal;
  const Pose before = state.pose;
  EXPECT_TRUE(updater.update(state, on_side, true, 0.0, 0));
  EXPECT_GT(positionError(before, state.pose) + orientationError(before, state.pose), 0.0);
  // Far from every side: not attributed, the pose stays.
  const Pose after = state.pose;
  const Eigen::Vector2d centre = 0.25 * (state.projected[0].a + state.projected[1].a + state.projected[2].a +
                                         state.projected[3].a);
  EXPECT_FALSE(updater.update(state, centre, true, 0.0, 0));
  EXPECT_EQ(positionError(after, state.pose), 0.0);
}

TEST(TrackerInitializer, NeighbourHorizonsScaleByPixelsAndStayApart)
{
  // Horizons are given for 128x128 and scale by the pixel count (the same events per pixel);
  // the loss monitor's is its own: widening the Hough filter's leaves it alone.
  TrackingGeometry g = dvs128Geometry();
  g.width = 640;
  g.height = 480;
  LineTrackerParams params;
  params.hough.neighbour_filter_events = 1500;
  params.hough.neighbour_same_polarity = true;
  const TrackerInitializer init(g, params);
  EXPECT_EQ(init.houghParams().neighbour_filter_events, 28125);  // 1500 * 640 * 480 / 128^2
  EXPECT_TRUE(init.houghParams().neighbour_same_polarity);
  EXPECT_EQ(init.scaledNeighbourHorizon(params.loss_neighbour_events), 9375);
  params.init_scale_with_sensor = false;
  EXPECT_EQ(TrackerInitializer(g, params).scaledNeighbourHorizon(500), 500);
}

TEST(TrackingGeometry, SharedCornersProjectAsEverySegmentAlone)
{
  // The square's sides share their corners: each corner is transformed and projected once, and
  // every projected field is exactly what projecting each segment on its own gives, also when
  // corners lie behind the camera or out of the image.
  TrackingGeometry shared = dvs128Geometry();
  shared.indexSharedEndpoints();
  const TrackingGeometry alone = dvs128Geometry();
  ASSERT_EQ(shared.shared_endpoint.size(), 2 * shared.map.segments.size());
  EXPECT_EQ(std::count_if(shared.shared_endpoint.begin(), shared.shared_endpoint.end(), [](int c) { return c >= 0; }), 4);
  EXPECT_TRUE(alone.shared_endpoint.empty());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int partly_behind = 0;
  for (int trial = 0; trial < 200; ++trial)
  {
    // From in front, beside, and (some) with the map's plane through the camera.
    const Eigen::Vector3d eye(0.8 * u(rng), 0.8 * u(rng), trial % 4 == 0 ? 0.3 * u(rng) : 0.4 + 2 * std::abs(u(rng)));
    const Pose pose = lookAt(eye, {0.6 * u(rng), 0.6 * u(rng), 0}, {0, 1, 0}, u(rng));
    std::vector<ProjectedSegment> a(shared.map.segments.size()), b(shared.map.segments.size());
    for (const bool visibility : {true, false})
    {
      shared.project(pose, visibility, a);
      alone.project(pose, visibility, b);
      for (size_t i = 0; i < a.size(); ++i)
      {
        SCOPED_TRACE("trial " + std::to_string(trial) + " segment " + std::to_string(i));
        ASSERT_EQ(a[i].pc0, b[i].pc0);
        ASSERT_EQ(a[i].pc1, b[i].pc1);
        ASSERT_EQ(a[i].in_front, b[i].in_front);
        ASSERT_EQ(a[i].t0, b[i].t0);
        ASSERT_EQ(a[i].t1, b[i].t1);
        ASSERT_EQ(a[i].visible, b[i].visible);
        ASSERT_EQ(a[i].visible_length, b[i].visible_length);
        if (!a[i].in_front)
          continue;
        ASSERT_EQ(a[i].a, b[i].a);
        ASSERT_EQ(a[i].b, b[i].b);
        ASSERT_EQ(a[i].normal, b[i].normal);
        ASSERT_EQ(a[i].length, b[i].length);
      }
    }
    partly_behind += std::any_of(a.begin(), a.end(), [](const ProjectedSegment& s) { return s.clipped(); }) ? 1 : 0;
  }
  EXPECT_GT(partly_behind, 0);  // the case where a shared corner's pixel must not be reused
}

TEST(TrackingGeometry, ASegmentPartlyBehindTheCameraIsClippedOnItsOwnImageLine)
{
  // A wide lens close to the square at a steep angle: a corner behind the camera. The two sides
  // meeting there are clipped at the near plane: in front, their image lines are the lines of
  // the map sides (every point of a side in front projects onto its clipped segment's line),
  // their linearisation from the world points usedEndpoints() gives is the one the projection's
  // camera points give, and the side wholly in front is untouched.
  TrackingGeometry g = dvs128Geometry();
  g.indexSharedEndpoints();
  // The camera 0.1 m above the square near its corner (0.45, 0.45), looking across it towards
  // the opposite corner: the near corner is behind it, the other three in front.
  const Pose pose = dvs_calibration::lookAt({0.35, 0.35, 0.1}, {-0.45, -0.45, 0.0}, {0, 0, 1}, 0);
  std::vector<ProjectedSegment> proj(g.map.segments.size());
  g.project(pose, true, proj);
  int clipped = 0;
  for (size_t i = 0; i < proj.size(); ++i)
  {
    SCOPED_TRACE("segment " + std::to_string(i));
    const MapSegment& m = g.map.segments[i];
    const ProjectedSegment& s = proj[i];
    const bool behind0 = pose.toCamera(m.p0_world).z() <= g.min_depth_m,
               behind1 = pose.toCamera(m.p1_world).z() <= g.min_depth_m;
    ASSERT_EQ(s.in_front, !(behind0 && behind1));
    ASSERT_EQ(s.clipped(), behind0 != behind1);
    if (!s.clipped())
      continue;
    ++clipped;
    EXPECT_EQ(s.t0 != 0, behind0);
    const double t = behind0 ? s.t0 : s.t1;  // where the part in front begins or ends
    EXPECT_GT(t, 0.0);
    EXPECT_LT(t, 1.0);
    EXPECT_NEAR(s.pc0.z() * (s.t0 != 0) + s.pc1.z() * (s.t1 != 1), g.min_depth_m, 1e-12);
    for (double t = 0; t <= 1.0; t += 0.05)
    {
      const Eigen::Vector3d pc = pose.toCamera(m.p0_world + t * (m.p1_world - m.p0_world));
      if (pc.z() > g.min_depth_m)
        EXPECT_NEAR(s.normal.dot(g.k.project(pc) - s.a), 0.0, 1e-6 * (1 + s.length));
    }
    Eigen::Vector3d w0, w1;
    g.usedEndpoints(static_cast<int>(i), s, w0, w1);
    EXPECT_LT((pose.toCamera(w0) - s.pc0).norm(), 1e-12);
    EXPECT_LT((pose.toCamera(w1) - s.pc1).norm(), 1e-12);
    PointMoments moments;
    for (int j = 0; j < 10; ++j)
      moments.add(s.a + (0.1 * j) * (s.b - s.a) + Eigen::Vector2d(0.3, -0.2), 1.0);
    SegmentNormalEquations from_world, from_camera;
    ASSERT_TRUE(linearizeSegment(g.k, pose, w0, w1, moments, 10, from_world));
    ASSERT_TRUE(linearizeSegment(g.k, s.pc0, s.pc1, s.a, s.b, moments, 10, from_camera));
    EXPECT_LT((from_world.H - from_camera.H).norm(), 1e-6 * from_camera.H.norm());
    EXPECT_LT((from_world.g - from_camera.g).norm(), 1e-6 * (1 + from_camera.g.norm()));
  }
  EXPECT_EQ(clipped, 2);
}

TEST(EventUpdater, LinearisesAtAPoseMovedWithoutProjection)
{
  // The IMU propagator moves the pose without projecting the map: the next solve must linearise
  // at the moved pose (the projection it would otherwise reuse is of the pose before).
  TrackingGeometry g = dvs128Geometry();
  g.indexSharedEndpoints();
  LineTrackerParams params;
  params.estimator.extra_relinearizations = 0;
  params.solve_min_offset_px = 0;  // every event solved
  EstimatorState state;
  state.resize(g.map.segments.size(), params.buffer_size);
  EventUpdater updater(g, params);
  ASSERT_EQ(updater.start(state, kFront), 4);
  Vector6d nudge;
  nudge << 0.01, -0.02, 0.015, 0.02, 0.01, -0.03;
  state.pose.applyCameraIncrement(nudge);
  const Pose moved = state.pose;
  const ProjectedSegment s = state.projected[1];
  ASSERT_TRUE(updater.update(state, 0.5 * (s.a + s.b) + 0.3 * s.normal, true, 0.0, 1000));
  ASSERT_EQ(updater.solves(), 1u);
  SegmentNormalEquations expected;
  ASSERT_TRUE(linearizeSegment(g.k, moved, g.map.segments[1].p0_world, g.map.segments[1].p1_world,
                               state.buffers[1], expected));
  EXPECT_EQ(state.equations[1].H, expected.H);
  EXPECT_EQ(state.equations[1].g, expected.g);
  // And at the pose of its projection, the cached projection gives the same equations.
  SegmentNormalEquations cached;
  const ProjectedSegment& now = state.projected[1];
  ASSERT_EQ(state.projected_at.R_camera_world, state.pose.R_camera_world);
  ASSERT_TRUE(linearizeSegment(g.k, now.pc0, now.pc1, now.a, now.b, state.buffers[1], cached));
  ASSERT_TRUE(linearizeSegment(g.k, state.pose, g.map.segments[1].p0_world, g.map.segments[1].p1_world,
                               state.buffers[1], expected));
  EXPECT_EQ(cached.H, expected.H);
  EXPECT_EQ(cached.g, expected.g);
}

TEST(EventUpdater, SolvesEveryEventBelowTheSolveRateAndAtTheRateAbove)
{
  const TrackingGeometry g = dvs128Geometry();
  LineTrackerParams params;
  params.max_solve_rate = 200000;  // a solve per 5 us, bursts of 1 ms (200 solves) let through
  params.solve_min_offset_px = 0;  // (events on the line would hold the solve back)
  EstimatorState state;
  state.resize(g.map.segments.size(), params.buffer_size);
  EventUpdater updater(g, params);
  updater.start(state, kFront);
  const ProjectedSegment s = state.projected[0];
  const auto on_side = [&](int i) { return Eigen::Vector2d(s.a + (0.2 + 0.6 * (i % 97) / 97.0) * (s.b - s.a)); };
  // 100 events 20 us apart (50,000 events/s, under the rate): each one solved.
  int64_t t = 1000000;
  for (int i = 0; i < 100; ++i, t += 20000)
    ASSERT_TRUE(updater.update(state, on_side(i), true, 0.0, t));
  EXPECT_EQ(updater.solves(), 100u);
  // 20,000 events 0.1 us apart (2 ms at 10 M events/s): the first ones while the bucket lasts
  // (it refilled during the slow part: 1 ms = 200 solves), then one per 5 us.
  for (int i = 0; i < 20000; ++i, t += 100)
    ASSERT_TRUE(updater.update(state, on_side(i), true, 0.0, t));
  const uint64_t dense = updater.solves() - 100;
  EXPECT_GE(dense, 200u + 2000000 / 5000 - 2);
  EXPECT_LE(dense, 200u + 2000000 / 5000 + 2);
  // Event time going back (jittered time stamps) holds no solve back once the rate allows.
  const uint64_t before = updater.solves();
  t += 1000000;
  for (int i = 0; i < 10; ++i)
    ASSERT_TRUE(updater.update(state, on_side(i), true, 0.0, t - 20000 * i));
  EXPECT_EQ(updater.solves() - before, 10u);
  // 0: every attributed event is solved whatever the rate.
  params.max_solve_rate = 0;
  const uint64_t unlimited = updater.solves();
  for (int i = 0; i < 1000; ++i, t += 1)
    ASSERT_TRUE(updater.update(state, on_side(i), true, 0.0, t));
  EXPECT_EQ(updater.solves() - unlimited, 1000u);
}

TEST(EventUpdater, SegmentsWithoutEventsAreReLinearisedRoundRobin)
{
  // Events on one side only, the pose moving with them: that side is re-linearised at every
  // solve, and the round robin (which skips a segment its own events keep fresh) still reaches
  // each of the other three within 2n = 8 solves.
  const TrackingGeometry g = dvs128Geometry();
  LineTrackerParams params;
  params.max_solve_rate = 0;
  params.solve_min_offset_px = 0;  // every event solved
  EstimatorState state;
  state.resize(g.map.segments.size(), params.buffer_size);
  EventUpdater updater(g, params);
  ASSERT_EQ(updater.start(state, kFront), 4);
  const ProjectedSegment s = state.projected[0];
  const int n = static_cast<int>(state.equations.size());
  const auto event = [&](int i) {
    return Eigen::Vector2d(s.a + (0.2 + 0.6 * (i % 31) / 31.0) * (s.b - s.a) + 0.7 * s.normal);
  };
  // The first solve re-linearises at the start's pose (x = 0, as seeded): count from there.
  int64_t t = 1000000;
  ASSERT_TRUE(updater.update(state, event(1), true, 0.0, t));
  std::vector<int> last_change(n, 1);
  std::vector<int> longest(n, 0);
  std::vector<Vector6d> x_lin(n);
  for (int j = 0; j < n; ++j)
    x_lin[j] = state.equations[j].x_lin;
  for (int i = 2; i <= 200; ++i)
  {
    t += 20000;
    ASSERT_TRUE(updater.update(state, event(i), true, 0.0, t));
    for (int j = 0; j < n; ++j)
      if (state.equations[j].x_lin != x_lin[j])
      {
        longest[j] = std::max(longest[j], i - last_change[j]);
        last_change[j] = i;
        x_lin[j] = state.equations[j].x_lin;
      }
  }
  ASSERT_EQ(updater.solves(), 200u);
  EXPECT_EQ(longest[0], 1);
  for (int j = 1; j < n; ++j)
  {
    EXPECT_GT(last_change[j], 200 - 2 * n) << "segment " << j;
    EXPECT_GE(longest[j], 1) << "segment " << j;
    EXPECT_LE(longest[j], 2 * n) << "segment " << j;
  }
}

TEST(EventUpdater, ReusesTheFactorOfTheInformationWhileItChangesLittle)
{
  // The same 400 events into updaters that factor the damped information at every solve, at
  // most every 4th (its diagonal allowed to change 100 %), only when the diagonal changed
  // (tolerance 0), or when it changed by 5 % (at most every 1000th). The first step after the
  // start is the same in all (all factor anew); the counts follow the rules; a refresh() (quality
  // check) makes the next solve factor anew; the reused factors steer the pose to nearly the same
  // place (the information changes little from event to event).
  const TrackingGeometry g = dvs128Geometry();
  LineTrackerParams every, fourth, on_change, tolerant;
  every.factor_every_solves = 1;
  fourth.factor_every_solves = 4;
  fourth.factor_information_change = 1.0;
  on_change.factor_every_solves = 1000;
  on_change.factor_information_change = 0.0;
  tolerant.factor_every_solves = 1000;
  tolerant.factor_information_change = 0.05;
  for (LineTrackerParams* p : {&every, &fourth, &on_change, &tolerant})
    p->solve_min_offset_px = 0;  // every event solved
  const LineTrackerParams* params[4] = {&every, &fourth, &on_change, &tolerant};
  std::vector<EstimatorState> states(4);
  std::vector<EventUpdater> updaters;
  for (int k = 0; k < 4; ++k)
  {
    states[k].resize(g.map.segments.size(), params[k]->buffer_size);
    updaters.emplace_back(g, *params[k]);
    updaters[k].start(states[k], kFront);
  }
  const ProjectedSegment s0 = states[0].projected[0], s1 = states[0].projected[1];
  // Events 0.6 px off two sides, as if the square had moved.
  const auto event = [&](int i) {
    const ProjectedSegment& s = i % 2 ? s1 : s0;
    return Eigen::Vector2d(s.a + (0.1 + 0.8 * (i % 37) / 37.0) * (s.b - s.a) + 0.6 * s.normal);
  };
  int64_t t = 1000000;
  for (int i = 0; i < 400; ++i, t += 20000)
  {
    for (int k = 0; k < 4; ++k)
      ASSERT_TRUE(updaters[k].update(states[k], event(i), true, 0.0, t));
    if (i == 0)
      for (int k = 1; k < 4; ++k)
      {
        EXPECT_EQ(states[0].pose.R_camera_world, states[k].pose.R_camera_world);
        EXPECT_EQ(states[0].pose.t_camera_world, states[k].pose.t_camera_world);
      }
  }
  for (int k = 0; k < 4; ++k)
    EXPECT_EQ(updaters[k].solves(), 400u);
  EXPECT_EQ(updaters[0].factorizations(), 400u);
  EXPECT_EQ(updaters[1].factorizations(), 100u);
  EXPECT_EQ(updaters[2].factorizations(), 400u);  // every event changes the information a little
  EXPECT_GT(updaters[3].factorizations(), 2u);      // 5 % of change is reached now and then...
  EXPECT_LT(updaters[3].factorizations(), 200u);    // ...but not at every other solve
  const Pose& exact = states[0].pose;
  EXPECT_GT(positionError(kFront, exact), 1e-3);  // the events moved the pose...
  for (int k = 1; k < 4; ++k)
  {
    EXPECT_LT(positionError(exact, states[k].pose), 0.02 * positionError(kFront, exact)) << k;  // ...all alike
    EXPECT_LT(orientationError(exact, states[k].pose), 0.02 * orientationError(kFront, exact)) << k;
  }
  // A quality check may change the damping and the visibility: the next solve factors anew.
  const uint64_t before = updaters[1].factorizations();
  updaters[1].refresh(states[1], -1);  // (the event rate not known)
  ASSERT_TRUE(updaters[1].update(states[1], event(400), true, 0.0, t));
  EXPECT_EQ(updaters[1].factorizations(), before + 1);
}

TEST(EventUpdater, EventsOnTheirLinesWaitAndTheirStepsComeWithTheNextSolve)
{
  // solve_min_offset_px: events on their projected segments hold the solve back (no news for
  // the pose); the next solve takes their damped steps too, so that the pose ends where solving
  // every event takes it, with fewer solves.
  const TrackingGeometry g = dvs128Geometry();
  LineTrackerParams every, gated;
  every.max_solve_rate = gated.max_solve_rate = 0;
  every.solve_min_offset_px = 0;
  gated.solve_min_offset_px = 0.5;
  EstimatorState se, sg;
  se.resize(g.map.segments.size(), every.buffer_size);
  sg.resize(g.map.segments.size(), gated.buffer_size);
  EventUpdater ue(g, every), ug(g, gated);
  ue.start(se, kFront);
  ug.start(sg, kFront);
  const ProjectedSegment s0 = se.projected[0], s1 = se.projected[1];
  // 40 events on side 0's projected line: solved 40 times, or not at all.
  int64_t t = 1000000;
  for (int i = 0; i < 40; ++i, t += 20000)
  {
    const Eigen::Vector2d on_line = s0.a + (0.1 + 0.8 * i / 40.0) * (s0.b - s0.a);
    ASSERT_TRUE(ue.update(se, on_line, true, 0.0, t));
    ASSERT_TRUE(ug.update(sg, on_line, true, 0.0, t));
  }
  EXPECT_EQ(ue.solves(), 40u);
  EXPECT_EQ(ug.solves(), 0u);
  // Unless the caller says the pose moved between events (an IMU's prediction): then no hold.
  EstimatorState sp;
  sp.resize(g.map.segments.size(), gated.buffer_size);
  EventUpdater up(g, gated);
  up.start(sp, kFront);
  for (int i = 0; i < 40; ++i)
    ASSERT_TRUE(up.update(sp, s0.a + (0.1 + 0.8 * i / 40.0) * (s0.b - s0.a), true, 0.0, 1000000 + 20000 * i, nullptr, false));
  EXPECT_EQ(up.solves(), 40u);
  // Then events 0.6 px off two sides, as if the square had moved, spread across +-0.5 px as the
  // pixel grid spreads them: the first one is solved at once; once the pose follows them, the
  // events lie closer and solves are held back.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> spread(-0.5, 0.5);
  for (int i = 0; i < 400; ++i, t += 20000)
  {
    const ProjectedSegment& s = i % 2 ? s1 : s0;
    const Eigen::Vector2d off = s.a + (0.1 + 0.8 * (i % 37) / 37.0) * (s.b - s.a) + (0.6 + (i > 0 ? spread(rng) : 0.0)) * s.normal;
    ASSERT_TRUE(ue.update(se, off, true, 0.0, t));
    ASSERT_TRUE(ug.update(sg, off, true, 0.0, t));
    if (i == 0)
      EXPECT_EQ(ug.solves(), 1u);
  }
  EXPECT_EQ(ue.solves(), 440u);
  EXPECT_LT(ug.solves(), 300u);
  const double moved = positionError(kFront, se.pose);
  EXPECT_GT(moved, 1e-3);  // the events moved the pose...
  EXPECT_LT(positionError(se.pose, sg.pose), 0.05 * moved);  // ...and both alike
  EXPECT_LT(orientationError(se.pose, sg.pose), 0.05 * orientationError(kFront, se.pose));
}

namespace
{
// Counts `n` events in `monitor`, the first `attributed` of them attributed; the others along two
// rows of pixels (an edge: next to each other) or at random pixels of the sensor (noise).
void countEvents(LossMonitor& monitor, int n, int attributed, bool structure, int width = 128, int height = 128,
                 unsigned seed = 1)
{
  std::mt19937 rng(seed);
  for (int i = 0; i < n; ++i)
  {
    const int x = structure ? (i / 2) % width : static_cast<int>(rng() % static_cast<unsigned>(width));
    const int y = structure ? 7 + i % 2 : static_cast<int>(rng() % static_cast<unsigned>(height));
    monitor.countEvent(i < attributed, x, y);
  }
}
// The DVS128 square tracked from kFront, for the loss monitor's checks.
class LossMonitorTest : public ::testing::Test
{
protected:
  void SetUp() override
  {
    state.resize(g.map.segments.size(), params.buffer_size);
    updater.start(state, kFront);
  }
  const TrackingGeometry g = dvs128Geometry();
  LineTrackerParams params;
  EstimatorState state;
  EventUpdater updater{g, params};
};
}  // namespace

TEST_F(LossMonitorTest, NamesWhyTheTrackIsLost)
{
  LossMonitor monitor(params, 0, 0, 500);  // no sensor size: the fixed ratio only
  countEvents(monitor, params.quality_check_interval, params.quality_check_interval, true);
  EXPECT_TRUE(monitor.due());
  EXPECT_EQ(monitor.check(state), "");
  EXPECT_FALSE(monitor.due());

  // Attribution collapsed: 1 of 512 events attributed.
  countEvents(monitor, params.quality_check_interval, 1, true);
  EXPECT_NE(monitor.check(state).find("attribution collapsed"), std::string::npos);

  // The square far outside the view.
  updater.start(state, lookAt({5, 0, 1.6}, {5, 0, 0}, {0, 1, 0}));
  EXPECT_NE(monitor.check(state).find("segments left the view (0 visible)"), std::string::npos);

  state.pose.t_camera_world.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(monitor.check(state), "the pose is not finite");
}

// partial_view_grace_s: two sides meeting at a corner may be all that is in view for that long
// (event time); parallel sides, one side, or longer: lost. 0 loses at once.
TEST_F(LossMonitorTest, ABriefPartialViewOnACornerIsNoLoss)
{
  const int n = params.quality_check_interval;
  const auto check = [&](LossMonitor& m, double t_s) {
    countEvents(m, n, n, true);
    return m.check(state, std::llround(t_s * 1e9));
  };
  const auto showOnly = [&](std::initializer_list<int> sides) {
    for (size_t i = 0; i < state.projected.size(); ++i)
      state.projected[i].visible = std::find(sides.begin(), sides.end(), static_cast<int>(i)) != sides.end();
  };
  ASSERT_EQ(state.projected.size(), 4u);  // the square's sides in order: 0 and 1 meet, 0 and 2 are parallel
  params.partial_view_grace_s = 0;
  LossMonitor at_once(params, 0, 0, 500);
  showOnly({0, 1});
  EXPECT_EQ(check(at_once, 1.0), "segments left the view (2 visible)");

  params.partial_view_grace_s = 0.05;
  LossMonitor monitor(params, 0, 0, 500);
  EXPECT_EQ(check(monitor, 1.0), "");
  EXPECT_EQ(check(monitor, 1.049), "");
  EXPECT_EQ(check(monitor, 1.05), "segments left the view (2 visible)");
  // Enough in view again: the next partial view has its own grace.
  monitor.restart();
  showOnly({0, 1, 2, 3});
  EXPECT_EQ(check(monitor, 2.0), "");
  showOnly({1, 2});
  EXPECT_EQ(check(monitor, 2.01), "");
  showOnly({0, 1, 2});
  EXPECT_EQ(check(monitor, 2.02), "");
  showOnly({2, 3});
  EXPECT_EQ(check(monitor, 2.06), "");
  EXPECT_EQ(check(monitor, 2.1), "");
  EXPECT_EQ(check(monitor, 2.11), "segments left the view (2 visible)");
  // Parallel sides or one side: lost at once.
  monitor.restart();
  showOnly({0, 2});
  EXPECT_EQ(check(monitor, 3.0), "segments left the view (2 visible)");
  monitor.restart();
  showOnly({3});
  EXPECT_EQ(check(monitor, 4.0), "segments left the view (1 visible)");
}

TEST_F(LossMonitorTest, AttributionIsComparedWithChanceOnLargeNoisySensors)
{
  // The same square and pose, counted against a 640x480 image: its attribution bands cover a
  // few per mille of the image, so 8 of 512 events (1.6 %, under min_attributed_ratio) are
  // still several times chance, while 1 of 512 is not.
  LossMonitor large(params, 640, 480, 9375), small(params, 128, 128, 500);
  countEvents(large, params.quality_check_interval, 8, true, 640, 480);
  countEvents(small, params.quality_check_interval, 8, true);
  EXPECT_EQ(large.check(state), "");
  EXPECT_NE(small.check(state).find("attribution collapsed"), std::string::npos);
  countEvents(large, params.quality_check_interval, 1, true, 640, 480);
  EXPECT_NE(large.check(state).find("attribution collapsed"), std::string::npos);
}

TEST_F(LossMonitorTest, NoiseAloneSaysNothingAgainstThePose)
{
  // At chance level (1 of 512 attributed) the track is lost when the other events are an edge
  // the map does not explain, not when they are background noise (the camera paused); with
  // min_unattributed_structure 0 every collapse is a loss (the test off).
  LossMonitor monitor(params, 640, 480, 9375);
  // Noise: warm the activity up with a few intervals' worth, then count one interval.
  for (unsigned seed = 1; seed <= 40; ++seed)
  {
    countEvents(monitor, params.quality_check_interval, 1, false, 640, 480, seed);
    EXPECT_EQ(monitor.check(state), "") << "interval " << seed;
  }
  countEvents(monitor, params.quality_check_interval, 1, true, 640, 480);
  const std::string reason = monitor.check(state);
  EXPECT_NE(reason.find("attribution collapsed"), std::string::npos) << reason;
  EXPECT_NE(reason.find("next to each other"), std::string::npos) << reason;

  params.min_unattributed_structure = 0;
  LossMonitor any(params, 640, 480, 9375);
  countEvents(any, params.quality_check_interval, 1, false, 640, 480);
  EXPECT_NE(any.check(state).find("attribution collapsed"), std::string::npos);
}

// A track whose attributed share falls far below its own level is lost when the rest is
// structure and its buffers sit off their lines (a slip); not when the rest is noise, not while
// the buffers fit their lines, not with attribution_drop_ratio 0.
TEST_F(LossMonitorTest, AttributionDropBelowTheTracksLevelIsALoss)
{
  const int n = params.quality_check_interval;
  const auto offsetBuffers = [&](EstimatorState& st, double px) {
    for (size_t i = 0; i < st.buffers.size(); ++i)
    {
      const ProjectedSegment& seg = st.projected[i];
      for (int k = 0; k < st.buffers[i].capacity(); ++k)
        st.buffers[i].insert(seg.a + (seg.b - seg.a) * ((k + 0.5) / st.buffers[i].capacity()) + px * seg.normal, seg);
    }
  };
  const auto warmedUp = [&](const LineTrackerParams& p) {
    auto m = std::make_unique<LossMonitor>(p, 128, 128, 500);
    for (int k = 0; k < 20; ++k)  // the track's level: 90 % attributed
    {
      countEvents(*m, n, n * 9 / 10, true);
      EXPECT_EQ(m->check(state), "");
    }
    return m;
  };
  // The buffers still on their lines: a drop to 20 % is no loss.
  auto monitor = warmedUp(params);
  countEvents(*monitor, n, n / 5, true);
  EXPECT_EQ(monitor->check(state), "");

  offsetBuffers(state, 1.0);
  ASSERT_GE(meanResidualPx(state), 0.4);
  // A drop to 20 % with the rest an edge: lost, and says so.
  monitor = warmedUp(params);
  countEvents(*monitor, n, n / 5, true);
  const std::string reason = monitor->check(state);
  EXPECT_NE(reason.find("attribution dropped"), std::string::npos) << reason;
  // The same drop with the rest noise: no loss.
  monitor = warmedUp(params);
  countEvents(*monitor, n, n / 5, false);
  EXPECT_EQ(monitor->check(state), "");
  // A smaller drop (to 40 %, above 0.35 x 90 %): no loss.
  monitor = warmedUp(params);
  countEvents(*monitor, n, n * 2 / 5, true);
  EXPECT_EQ(monitor->check(state), "");
  // The rule off.
  LineTrackerParams off = params;
  off.attribution_drop_ratio = 0;
  monitor = warmedUp(off);
  countEvents(*monitor, n, n / 5, true);
  EXPECT_EQ(monitor->check(state), "");
}

namespace
{
struct CountingPropagator : StatePropagator
{
  int propagated = 0, restarted = 0;
  int64_t last_t = -1;
  bool monotonic = true;
  void propagate(EstimatorState&, int64_t t_ns) override
  {
    monotonic &= t_ns >= last_t;
    last_t = t_ns;
    ++propagated;
  }
  void restart(const EstimatorState&, int64_t) override { ++restarted; }
  bool active(int64_t) const override { return true; }
  int64_t maxBridgeNs() const override { return 0; }
};
}  // namespace

TEST(LineTracker, PropagatorRunsBeforeEveryTrackingUpdate)
{
  const SyntheticSequence seq = slowRoll(0.6);
  LineTracker tracker(idealCamera(), defaultSquareMap());
  auto propagator = std::make_shared<CountingPropagator>();
  tracker.setPropagator(propagator);
  uint64_t tracking_events = 0;
  for (const auto& e : seq.events)
  {
    const bool tracking = tracker.state() == TrackerState::kTracking;
    tracker.processEvent(e);
    tracking_events += tracking ? 1 : 0;
  }
  ASSERT_EQ(tracker.state(), TrackerState::kTracking);
  EXPECT_EQ(propagator->restarted, static_cast<int>(tracker.stats().initializations));
  EXPECT_EQ(static_cast<uint64_t>(propagator->propagated), tracking_events);
  EXPECT_TRUE(propagator->monotonic);
}

TEST(LineTracker, ResetReachesEveryPart)
{
  const SyntheticSequence seq = slowRoll(0.6);
  LineTracker tracker(idealCamera(), defaultSquareMap());
  std::vector<Pose> first_run;
  for (const auto& e : seq.events)
    if (tracker.processEvent(e))
      first_run.push_back(tracker.pose());
  ASSERT_EQ(tracker.state(), TrackerState::kTracking);
  ASSERT_GT(first_run.size(), 100u);
  tracker.reset();
  EXPECT_EQ(tracker.state(), TrackerState::kInitializing);
  EXPECT_EQ(tracker.stats().events, 0u);
  EXPECT_EQ(tracker.lastLossReason(), "");
  // A reset tracker behaves exactly like a new one on the same events (nothing learned survives).
  std::vector<Pose> second_run;
  for (const auto& e : seq.events)
    if (tracker.processEvent(e))
      second_run.push_back(tracker.pose());
  ASSERT_EQ(second_run.size(), first_run.size());
  for (size_t i = 0; i < first_run.size(); ++i)
    ASSERT_EQ(positionError(first_run[i], second_run[i]), 0.0) << "update " << i;
}

TEST(LineTracker, RestartsAndSaysSoWhenEventTimeGoesBack)
{
  // A recording played twice into a running tracker (a bag looping): the second pass starts
  // 0.6 s earlier than the first ended.
  const SyntheticSequence seq = slowRoll(0.6);
  LineTracker tracker(idealCamera(), defaultSquareMap());
  for (const auto& e : seq.events)
    tracker.processEvent(e);
  ASSERT_EQ(tracker.state(), TrackerState::kTracking);
  const uint64_t first_pass_inits = tracker.stats().initializations;
  tracker.processEvent(seq.events.front());
  EXPECT_EQ(tracker.stats().time_jumps, 1u);
  EXPECT_EQ(tracker.state(), TrackerState::kInitializing);
  EXPECT_NE(tracker.lastLossReason().find("event time went back by"), std::string::npos) << tracker.lastLossReason();
  for (const auto& e : seq.events)
    tracker.processEvent(e);
  EXPECT_EQ(tracker.state(), TrackerState::kTracking);  // tracked again on the second pass
  EXPECT_EQ(tracker.stats().initializations, 2 * first_pass_inits);
  EXPECT_EQ(tracker.stats().time_jumps, 1u);
  EXPECT_EQ(tracker.stats().events, 2 * seq.events.size() + 1);
}

TEST(LineTracker, EventsOutsideTheSensorAreCounted)
{
  LineTracker tracker(idealCamera(), defaultSquareMap());
  dvs_driver::Event e;
  e.x = 200;  // a 240-wide recording read as 128x128
  e.y = 10;
  EXPECT_FALSE(tracker.processEvent(e));
  e.x = 10;
  e.y = 128;
  EXPECT_FALSE(tracker.processEvent(e));
  EXPECT_EQ(tracker.stats().events_outside_sensor, 2u);
}

TEST(LineTracker, NoPoseOnIsolatedNoiseSaysTheEventsDoNotPassTheNeighbourFilter)
{
  // Uniform background activity (no target): few events have two neighbours that fired among
  // the latest 500, so few vote, and the reason for no pose says so instead of blaming the map.
  LineTracker tracker(idealCamera(), defaultSquareMap());
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pixel(0, 127);
  const int n = 20000;
  dvs_driver::Event e;
  for (int i = 0; i < n; ++i)
  {
    e.x = static_cast<uint16_t>(pixel(rng));
    e.y = static_cast<uint16_t>(pixel(rng));
    e.t_ns = 100000LL * i;  // 10 k events/s, 2 s
    e.polarity = i % 2 == 0;
    EXPECT_FALSE(tracker.processEvent(e));
  }
  ASSERT_EQ(tracker.state(), TrackerState::kInitializing);
  const InitializerStats& is = tracker.initializerStats();
  EXPECT_EQ(is.events, static_cast<uint64_t>(n));
  EXPECT_GT(is.events_voted, 0u);
  EXPECT_LT(is.events_voted * 10, is.events);
  const std::string why = is.noPoseReason();
  EXPECT_EQ(why.find(std::to_string(is.events_voted) + " of 20000 events"), 0u) << why;
  EXPECT_NE(why.find("isolated (noise)"), std::string::npos) << why;
  EXPECT_NE(why.find("init_neighbour_same_polarity: true"), std::string::npos) << why;
  EXPECT_NE(is.json().find("\"events_voted\": " + std::to_string(is.events_voted)), std::string::npos) << is.json();
}

TEST(LineTracker, InitialiserCountsOnlyTheEventsBeforeTracking)
{
  const SyntheticSequence seq = slowRoll(0.6);
  LineTracker tracker(idealCamera(), defaultSquareMap());
  uint64_t before_tracking = 0;
  for (const auto& e : seq.events)
  {
    before_tracking += tracker.state() == TrackerState::kTracking ? 0 : 1;
    tracker.processEvent(e);
  }
  ASSERT_EQ(tracker.state(), TrackerState::kTracking);
  const InitializerStats& is = tracker.initializerStats();
  EXPECT_EQ(is.events, before_tracking);
  EXPECT_LT(is.events, tracker.stats().events);
  EXPECT_GT(is.events_voted, 0u);
  EXPECT_LE(is.events_voted, is.events);
}

TEST(InitializerStats, NoPoseReasonNamesTheStageThatStoppedTheDetections)
{
  InitializerStats s;
  EXPECT_EQ(s.noPoseReason(), "no events reached the initialiser");
  // Enough voted events and attempts, no polygon: the segments are named, not the filter.
  s.events = 1000;
  s.events_voted = 400;
  s.attempts = 3;
  s.segments = 7;
  std::string why = s.noPoseReason();
  EXPECT_EQ(why.find("400 of 1000 events (40 %) passed the neighbour filter, 3 detection attempts: no image polygon"), 0u)
      << why;
  EXPECT_NE(why.find("among the 7 segments"), std::string::npos) << why;
  // Polygons found: each stage's count.
  s.polygons = 12;
  s.pose_failed = 5;
  s.coverage_failed = 4;
  s.too_oblique = 3;
  s.ambiguous = 2;
  s.unconfirmed = 1;
  why = s.noPoseReason();
  EXPECT_NE(why.find("12 image polygons: 5 gave no pose, 4 were not backed"), std::string::npos) << why;
  EXPECT_NE(why.find("3 were seen too far off the polygon's normal, 2 ambiguous, 1 unconfirmed"), std::string::npos) << why;
  // Too few voted events (under a tenth), or none enough for an attempt: the filter is named.
  s.events_voted = 99;
  EXPECT_NE(s.noPoseReason().find("isolated (noise)"), std::string::npos) << s.noPoseReason();
  s.events_voted = 400;
  s.attempts = 0;
  EXPECT_NE(s.noPoseReason().find("and 0 detection attempts ran"), std::string::npos) << s.noPoseReason();
}

TEST(LineTracker, CatchUpStartsFromThePoseOfTheLatestEvent)
{
  // A camera rolling at 400 deg/s (below init_max_roll_rate): the detection's pose fits the
  // refinement window's events, spread over tens of milliseconds, and lags the roll by half
  // their span; the catch-up runs the per-event update through them before the first pose.
  SyntheticEventParams sp;
  sp.k = PinholeK{115, 115, 63.5, 63.5};
  sp.duration_s = 0.4;
  const double rate = 400 * M_PI / 180;
  const PoseFunction roll = [rate](double t) {
    return lookAt({0.05, -0.03, 1.6}, {0.05, -0.03, 0}, {0, 1, 0}, rate * t);
  };
  const SyntheticSequence seq = generateSyntheticEvents(defaultSquareMap(), roll, sp);
  const auto firstPoseError = [&](bool catch_up, double* t_first) {
    LineTrackerParams p;
    p.init_catch_up = catch_up;
    LineTracker tracker(idealCamera(), defaultSquareMap(), p);
    for (const auto& e : seq.events)
      if (tracker.processEvent(e))
      {
        const double t = e.t_ns * 1e-9;
        *t_first = t;
        return orientationError(roll(t), tracker.pose()) * 180 / M_PI;
      }
    return -1.0;
  };
  double t_with = 0, t_without = 0;
  const double with = firstPoseError(true, &t_with), without = firstPoseError(false, &t_without);
  ASSERT_GE(with, 0) << "no pose with the catch-up";
  ASSERT_GE(without, 0) << "no pose without it";
  EXPECT_EQ(t_with, t_without);  // the same detection starts both
  // Measured: 2.9 deg without, 1.3 deg with (2026-11-26).
  EXPECT_GT(without, 2.0);  // the lag the catch-up removes
  EXPECT_LT(with, 0.6 * without) << "with " << with << " deg, without " << without << " deg";
}
