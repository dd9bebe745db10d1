// Screen in the loop, the math (no display): projection pipeline (Eq. 3.1-3.8, 3.15/3.16),
// homography fitting, alignment (Eq. 3.11-3.14), ordering of detected grids, line-distance
// measure, screen timing.
#include <dvs_screen_sim/screen_loop/alignment.h>
#include <dvs_screen_sim/screen_loop/grid_alignment.h>
#include <dvs_screen_sim/screen_loop/line_grid_check.h>
#include <dvs_screen_sim/screen_loop/projection_pipeline.h>
#include <dvs_screen_sim/screen_loop/screen_timing.h>
#include <dvs_screen_sim/event_simulator.h>
#include <dvs_screen_sim/trajectory.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace dvs_screen_sim;
using namespace dvs_screen_sim::screen_loop;

namespace
{
Pose virtualPose()
{
  return Pose::fromWorldCamera(orientationFromYawPitchRollDeg({8, -5, 12}), Eigen::Vector3d(0.1, -0.05, 1.2));
}

/// A "physical" homography ideal DVS px -> viewport of a DVS tilted in front of the screen: the
/// screen plane seen by a pinhole camera, composed with an arbitrary scaling to the viewport.
Eigen::Matrix3d physicalDvsToViewport(const dvs_calibration::CameraModel& cam)
{
  // Screen plane z=0 (metres), DVS at 0.3 m, yaw 15 deg, pitch -10 deg, shifted.
  const Pose T_screen_dvs = Pose::fromWorldCamera(orientationFromYawPitchRollDeg({15, -10, 3}), Eigen::Vector3d(0.02, -0.015, 0.3));
  // Screen point (X, Y, 0) -> DVS ideal pixel: K [r1 r2 t].
  const Eigen::Matrix3d R = T_screen_dvs.R_world_camera().transpose();
  const Eigen::Vector3d t = -R * T_screen_dvs.p_world_camera();
  Eigen::Matrix3d G;
  G.col(0) = R.col(0);
  G.col(1) = R.col(1);
  G.col(2) = t;
  const Eigen::Matrix3d screen_to_dvs = cam.cameraMatrix() * G;
  // Screen metres -> viewport: a 0.4 x 0.3 m window centred at the origin.
  Eigen::Matrix3d m_to_vp;
  m_to_vp << 2.0 / 0.4, 0, 0, 0, 2.0 / 0.3, 0, 0, 0, 1;
  return m_to_vp * screen_to_dvs.inverse();
}
}  // namespace

TEST(ProjectionPipeline, ViewMatrixMapsWorldToCamera)
{
  const Pose T = virtualPose();
  const Eigen::Matrix4d M = viewMatrix(T);
  const Eigen::Vector3d pw(0.3, -0.2, 0.05);
  const Eigen::Vector4d pc = M * pw.homogeneous();
  EXPECT_NEAR((pc.head<3>() - T.toCamera(pw)).norm(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(pc.w(), 1.0);
  // The camera centre maps to the origin.
  EXPECT_NEAR((M * T.p_world_camera().homogeneous()).head<3>().norm(), 0.0, 1e-12);
}

TEST(ProjectionPipeline, FocalLengthsMatchTheDvs)
{
  const auto cam = dvs_calibration::CameraModel::dvs128();  // fx = fy = 115, 128 x 128
  const VirtualFocalLengths f = matchedFocalLengths(cam);
  EXPECT_NEAR(f.fx, 115.0 / 63.5, 1e-12);   // Eq. 3.7
  EXPECT_NEAR(f.fy, -115.0 / 63.5, 1e-12);  // Eq. 3.8 (negative: viewport y up)
  EXPECT_NEAR(matchedFocalLengths(cam, 0.8).fx, 0.8 * 115.0 / 63.5, 1e-12);
  const Eigen::Matrix4d K = projectionMatrix(f);
  // Eq. 3.5: x_clip = f x, y_clip = f y, z_clip = 0, w_clip = z.
  const Eigen::Vector4d c = K * Eigen::Vector4d(0.2, -0.1, 2.0, 1.0);
  EXPECT_NEAR(c.x(), f.fx * 0.2, 1e-12);
  EXPECT_NEAR(c.y(), f.fy * -0.1, 1e-12);
  EXPECT_EQ(c.z(), 0.0);
  EXPECT_NEAR(c.w(), 2.0, 1e-12);
  // A point on the DVS image's left/top border (ideal pixel 0, principal point centred) lands
  // on the viewport's left/top border.
  ProjectionPipeline pipe(cam);
  const Pose T = virtualPose();
  const Eigen::Vector3d ray = Eigen::Vector3d((0 - 63.5) / 115.0, (0 - 63.5) / 115.0, 1.0) * 1.7;
  Eigen::Vector2d vp;
  ASSERT_TRUE(pipe.viewport(T, T.toWorld(ray), vp, false));
  EXPECT_NEAR(vp.x(), -1.0, 1e-12);
  EXPECT_NEAR(vp.y(), 1.0, 1e-12);
  EXPECT_THROW(matchedFocalLengths(cam, 0.0), std::invalid_argument);
}

TEST(ProjectionPipeline, ExpandedHomographyActsOnClipCoordinatesLikeHOnTheViewport)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  Eigen::Matrix3d H;
  H << 1.1 + u(rng), u(rng), u(rng), u(rng), 0.9 + u(rng), u(rng), 0.3 * u(rng), 0.3 * u(rng), 1.0;
  const Eigen::Matrix4d Hbar = expandHomography(H);
  // Eq. 3.16 layout.
  EXPECT_EQ(Hbar(0, 2), 0.0);
  EXPECT_EQ(Hbar(2, 0), 0.0);
  EXPECT_EQ(Hbar(2, 2), 1.0);
  EXPECT_EQ(Hbar(3, 3), H(2, 2));
  EXPECT_EQ(Hbar(0, 3), H(0, 2));
  EXPECT_EQ(Hbar(3, 1), H(2, 1));
  const auto cam = dvs_calibration::CameraModel::dvs128();
  ProjectionPipeline pipe(cam);
  pipe.setCorrection(H);
  const Pose T = virtualPose();
  for (int i = 0; i < 20; ++i)
  {
    const Eigen::Vector3d pw(2 * u(rng), 2 * u(rng), 0.0);
    Eigen::Vector2d vp0, vp1;
    ASSERT_TRUE(pipe.viewport(T, pw, vp0, false));
    ASSERT_TRUE(pipe.viewport(T, pw, vp1, true));
    EXPECT_NEAR((vp1 - applyHomography(H, vp0)).norm(), 0.0, 1e-12);
    EXPECT_EQ(pipe.clip(T, pw, true).z(), 0.0);  // nothing is depth-clipped
  }
  // The affine A maps the uncorrected viewport to the ideal DVS pixel (Eq. 3.12).
  const Eigen::Vector3d pw(0.15, 0.1, 0.0);
  Eigen::Vector2d vp, ideal;
  ASSERT_TRUE(pipe.viewport(T, pw, vp, false));
  ASSERT_TRUE(cam.projectIdeal(T.toCamera(pw), ideal));
  EXPECT_NEAR((applyHomography(pipe.viewportToIdealDvs(), vp) - ideal).norm(), 0.0, 1e-10);
}

TEST(Homography, FitRecoversAKnownHomographyAndRejectsBadInput)
{
  Eigen::Matrix3d H;
  H << 0.02, 0.003, -1.1, -0.002, -0.021, 1.2, 1e-4, -2e-4, 1.0;
  Points2d src, dst;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 5; ++j)
    {
      src.emplace_back(10 + 20 * i, 15 + 22 * j);
      dst.push_back(applyHomography(H, src.back()));
    }
  const Eigen::Matrix3d Hf = fitHomography(src, dst);
  for (size_t i = 0; i < src.size(); ++i)
    EXPECT_NEAR((applyHomography(Hf, src[i]) - dst[i]).norm(), 0.0, 1e-10);
  EXPECT_NEAR((Hf / Hf(2, 2) - H).norm(), 0.0, 1e-9);
  EXPECT_LT(transferError(Hf, src, dst).rms, 1e-10);
  // Round trip through the inverse.
  EXPECT_NEAR((applyHomography(Hf.inverse(), applyHomography(Hf, {33, 44})) - Eigen::Vector2d(33, 44)).norm(), 0.0,
              1e-9);
  // Noise: the residual is of the order of the noise.
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 0.01);
  Points2d noisy = dst;
  for (auto& p : noisy)
    p += Eigen::Vector2d(n(rng), n(rng));
  const auto e = transferError(fitHomography(src, noisy), src, noisy);
  EXPECT_GT(e.rms, 0.002);
  EXPECT_LT(e.rms, 0.02);

  EXPECT_THROW(fitHomography(Points2d(src.begin(), src.begin() + 3), Points2d(dst.begin(), dst.begin() + 3)),
               AlignmentError);
  EXPECT_THROW(fitHomography(src, Points2d(dst.begin(), dst.begin() + 5)), AlignmentError);
  Points2d line_src, line_dst;
  for (int i = 0; i < 6; ++i)
  {
    line_src.emplace_back(i, 2 * i);
    line_dst.emplace_back(3 * i, i);
  }
  EXPECT_THROW(fitHomography(line_src, line_dst), AlignmentError);
}

// The core claim of the thesis's correction: after alignment, the (misaligned) DVS sees every
// scene point exactly where a DVS at the virtual camera's pose would (Eq. 3.11-3.15).
TEST(Alignment, CorrectedPipelineMakesTheDvsSeeTheVirtualView)
{
  const auto cam = dvs_calibration::CameraModel::dvs128();
  const Eigen::Matrix3d H_true = physicalDvsToViewport(cam);  // ideal DVS px -> viewport
  ProjectionPipeline pipe(cam);
  AlignmentPattern pattern;
  pattern.centre_vp = applyHomography(H_true, {63.5, 63.5});
  pattern.spacing_vp = {0.08, 0.08};
  const Points2d vp = patternCentresViewport(pattern);
  ASSERT_EQ(vp.size(), 35u);
  EXPECT_GT(vp[0].y(), vp[34].y());  // row 0 at the top
  EXPECT_LT(vp[0].x(), vp[6].x());
  Points2d measured, desired;
  for (const auto& v : vp)
  {
    measured.push_back(applyHomography(H_true.inverse(), v));  // what the DVS sees
    desired.push_back(applyHomography(pipe.viewportToIdealDvs(), v));
  }
  const AlignmentResult r = computeAlignment(measured, vp, desired);
  EXPECT_LT(r.residual_dvs_px.rms, 1e-8);
  pipe.setCorrection(r.H);
  const Pose T = virtualPose();
  for (double x = -0.4; x <= 0.4; x += 0.1)
    for (double y = -0.3; y <= 0.3; y += 0.1)
    {
      const Eigen::Vector3d pw(x, y, 0.0);
      Eigen::Vector2d vp_corr, seen, ideal;
      ASSERT_TRUE(pipe.viewport(T, pw, vp_corr, true));
      seen = applyHomography(H_true.inverse(), vp_corr);
      ASSERT_TRUE(cam.projectIdeal(T.toCamera(pw), ideal));
      EXPECT_NEAR((seen - ideal).norm(), 0.0, 1e-7) << x << " " << y;
      // Without the correction the DVS sees it elsewhere (the test can fail).
      Eigen::Vector2d vp_raw;
      ASSERT_TRUE(pipe.viewport(T, pw, vp_raw, false));
      EXPECT_GT((applyHomography(H_true.inverse(), vp_raw) - ideal).norm(), 1.0);
    }
  // Noisy detections (0.1 px): the residual reports them.
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 0.1);
  for (auto& m : measured)
    m += Eigen::Vector2d(n(rng), n(rng));
  const AlignmentResult rn = computeAlignment(measured, vp, desired);
  EXPECT_GT(rn.residual_dvs_px.rms, 0.03);
  EXPECT_LT(rn.residual_dvs_px.rms, 0.2);
}

TEST(Alignment, DetectorOrderIsMappedBackToThePatternOrder)
{
  const auto cam = dvs_calibration::CameraModel::dvs128();
  const Eigen::Matrix3d H_true = physicalDvsToViewport(cam);
  for (bool square : {false, true})
  {
    AlignmentPattern pattern;
    if (square)
      pattern.rows = pattern.cols = 5;
    pattern.centre_vp = applyHomography(H_true, {63.5, 63.5});
    pattern.spacing_vp = {0.08, 0.08};
    const Points2d vp = patternCentresViewport(pattern);
    Points2d truth;
    for (const auto& v : vp)
      truth.push_back(applyHomography(H_true.inverse(), v));
    const int C = pattern.cols, R = pattern.rows;
    // The detector may report the grid rotated by 180 deg (or by 90 deg for a square grid).
    Points2d rotated(truth.size());
    for (int r = 0; r < R; ++r)
      for (int c = 0; c < C; ++c)
        rotated[static_cast<size_t>(R - 1 - r) * C + (C - 1 - c)] = truth[static_cast<size_t>(r) * C + c];
    for (const Points2d* in : {&truth, &rotated})
    {
      const Points2d ordered = orderLikePattern(*in, pattern, {63.5, 63.5});
      for (size_t i = 0; i < truth.size(); ++i)
        EXPECT_NEAR((ordered[i] - truth[i]).norm(), 0.0, 1e-12) << "square " << square << " i " << i;
    }
    if (square)
    {
      Points2d quarter(truth.size());  // rotated by 90 deg: detector (c, r) = pattern (r, C-1-c)
      for (int r = 0; r < R; ++r)
        for (int c = 0; c < C; ++c)
          quarter[static_cast<size_t>(c) * C + (C - 1 - r)] = truth[static_cast<size_t>(r) * C + c];
      const Points2d ordered = orderLikePattern(quarter, pattern, {63.5, 63.5});
      for (size_t i = 0; i < truth.size(); ++i)
        EXPECT_NEAR((ordered[i] - truth[i]).norm(), 0.0, 1e-12) << "quarter turn, i " << i;
    }
  }
}

TEST(LineGridCheck, DistancesOfEventsToExpectedLines)
{
  dvs_calibration::CameraIntrinsics k;
  k.width = k.height = 128;
  k.fx = k.fy = 100;
  k.cx = k.cy = 63.5;
  const dvs_calibration::CameraModel cam(k);  // no distortion: LUT = pixel centres
  const std::vector<ImageSegment> lines = {{{20.0, 0.0}, {20.0, 127.0}}};
  dvs_driver::EventVector ev;
  for (uint16_t y = 0; y < 128; ++y)
    for (int rep = 0; rep < 3; ++rep)
      ev.push_back({0, 20, y, true});
  auto st = eventLineDistances(ev, cam, lines);
  EXPECT_EQ(st.events_used, ev.size());
  EXPECT_NEAR(st.mean_event_distance, 0.0, 1e-6);
  EXPECT_NEAR(st.mean_line_offset, 0.0, 1e-6);
  // Events one column off: distance 1, offset 1; far events are ignored.
  for (auto& e : ev)
    e.x = 21;
  ev.push_back({0, 60, 5, false});
  st = eventLineDistances(ev, cam, lines);
  EXPECT_EQ(st.events_used, ev.size() - 1);
  EXPECT_NEAR(st.mean_event_distance, 1.0, 1e-5);
  EXPECT_NEAR(st.mean_line_offset, 1.0, 1e-5);
  // Two columns either side of the line in equal numbers: offset 0, distance 0.5.
  dvs_driver::EventVector both;
  for (uint16_t y = 0; y < 128; ++y)
  {
    both.push_back({0, 19, y, true});
    both.push_back({0, 20, y, true});
    both.push_back({0, 20, y, true});
    both.push_back({0, 21, y, true});
  }
  st = eventLineDistances(both, cam, lines);
  EXPECT_NEAR(st.mean_event_distance, 0.5, 1e-5);
  EXPECT_NEAR(st.mean_line_offset, 0.0, 1e-5);

  // Expected lines: a grid seen straight from 1 m lands at f * X / Z + c.
  const Pose T = Pose::fromWorldCamera(lookingAtWallOrientation(), Eigen::Vector3d(0, 0, 1.0));
  const auto img = expectedImageLines(cam, T, lineGrid(3, 2, 0.1));
  ASSERT_EQ(img.size(), 5u);
  EXPECT_NEAR(img[0].a.x(), 63.5 - 10.0, 1e-9);  // x = -0.1 m
  EXPECT_NEAR(img[3].a.y(), 63.5 + 5.0, 1e-9);   // y = -0.05 m is below the centre (image y down)
}

TEST(ScreenTiming, RefreshPeriodTimeScaleAndApparentMotion)
{
  RefreshPeriodEstimator est;
  EXPECT_EQ(est.period(), 0.0);
  double t = 10.0;
  for (int i = 0; i < 30; ++i)
  {
    est.addSwapTime(t);
    t += (i == 10) ? 2 * 0.016667 : 0.016667;  // one missed frame
  }
  EXPECT_NEAR(est.period(), 0.016667, 1e-9);

  // DVS clock 3 s ahead of the host, packets arriving 0.2-2 ms after their last event.
  DvsClockOffset clock;
  EXPECT_FALSE(clock.valid());
  const int64_t offset = 3000000000;
  for (int i = 0; i < 50; ++i)
  {
    const int64_t host = 1000000000LL + i * 1000000LL;
    clock.addPacket(host + offset - (200000 + (i * 37 % 19) * 100000), host);
  }
  ASSERT_TRUE(clock.valid());
  EXPECT_EQ(clock.offsetNs(), offset - 200000);
  EXPECT_EQ(clock.toDvsNs(5), 5 + offset - 200000);

  TimeScale ts{5.0};
  EXPECT_NEAR(ts.trajectoryTime(ts.playbackTime(1.234)), 1.234, 1e-12);
  EXPECT_EQ(ts.rescaleStampNs(5000000000), 1000000000);
  EXPECT_THROW(TimeScale{0.0}.validate(), std::invalid_argument);

  // A camera 1 m from the wall sliding at 0.5 m/s along x: the centre point moves
  // f_Ox * v * dt / Z viewport units = that * W / 2 window pixels per refresh.
  const auto cam = dvs_calibration::CameraModel::dvs128();
  ProjectionPipeline pipe(cam);
  LinearTrajectoryParams lp;
  lp.start_position = {0, 0, 1};
  lp.end_position = {1, 0, 1};
  lp.start_ypr_deg = lp.end_ypr_deg = Eigen::Vector3d::Zero();
  lp.duration = 2.0;
  LinearTrajectory traj(lp);
  const std::vector<Eigen::Vector3d> pts = {{0.25, 0.0, 0.0}};
  const double period = 1.0 / 60;
  const int W = 1280, H = 1024;
  const double expected = pipe.focalLengths().fx * 0.5 * period / 1.0 * W / 2;  // ~12.6 px
  EXPECT_NEAR(screenMotionPx(pipe, traj, pts, 0.5, period, W, H), expected, 1e-6);
  const MotionCheck mc = checkApparentMotion(pipe, traj, pts, 0.0, 1.0, period, TimeScale{1.0}, W, H);
  EXPECT_NEAR(mc.max_px_per_refresh, expected, 1e-3);
  EXPECT_FALSE(motionWarning(mc).empty());
  EXPECT_GT(mc.suggested_time_scale, expected - 1e-3);
  const MotionCheck slow = checkApparentMotion(pipe, traj, pts, 0.0, 1.0, period, TimeScale{mc.suggested_time_scale}, W, H);
  EXPECT_LE(slow.max_px_per_refresh, 1.0 + 1e-6);
  EXPECT_TRUE(motionWarning(slow).empty());
}

// A still camera filming a monitor: the simulator re-evaluates every pixel only when the
// monitor refreshes (not at every sample), and the events happen exactly at the refreshes.
TEST(VirtualMonitorSimulation, StillCameraReevaluatesPixelsOnlyAtRefreshes)
{
  dvs_calibration::CameraIntrinsics k;
  k.width = 32;
  k.height = 24;
  k.fx = k.fy = 40;
  k.cx = 15.5;
  k.cy = 11.5;
  const dvs_calibration::CameraModel cam(k);
  Scene scene;
  scene.background_reflectance = 0.1;
  SceneImage im;
  im.name = "monitor";
  im.width = 16;
  im.height = 12;
  im.top_left = {-0.4, 0.3};
  im.size = {0.8, 0.6};
  im.texels.assign(16 * 12, 0.1f);
  im.update_period = 0.01;
  im.update = [](int64_t frame, std::vector<float>& t) {
    for (size_t i = 0; i < t.size(); ++i)
      t[i] = ((i % 16) < 8) == (frame % 2 == 0) ? 0.9f : 0.1f;  // halves swap every refresh
  };
  scene.images.push_back(im);
  scene.finalize();
  const StaticTrajectory still(Pose::fromWorldCamera(lookingAtWallOrientation(), Eigen::Vector3d(0, 0, 0.5)));
  SimulationStats stats;
  const auto events = simulateEvents(cam, scene, still, 0.0, 0.1, EventModelConfig(), SamplingConfig(), 0, &stats);
  ASSERT_GT(events.size(), 1000u);
  for (const auto& e : events)
  {
    const int64_t r = e.t_ns % 10000000;
    EXPECT_LE(std::min(r, 10000000 - r), 1000) << e.t_ns;  // at a refresh (within 1 us)
  }
  const uint64_t pixels = 32 * 24;
  EXPECT_GT(stats.samples, 90u);                   // >= one sample per millisecond
  EXPECT_LE(stats.pixel_updates, 12 * pixels);     // ~10 refreshes (+ start), not ~100 samples
}
