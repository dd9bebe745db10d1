// The screen in the loop without hardware (issue 7, "Verification without hardware"): the
// software DVS sits at a misaligned pose (tilted, shifted) in front of a virtual monitor whose
// image is the OpenGL window read back. The alignment phase (blinking circle grid, detected in
// the DVS's events with dvs_calibration's detector) gives the correction H; a blinking line grid
// then drawn through the corrected pipeline must fall where a DVS at the virtual camera's pose
// would see it.
//
// Needs an X display: without $DISPLAY the test re-runs itself under
// `xvfb-run -a -s "-screen 0 1280x1024x24"`.
#include <dvs_calibration/event_window.h>
#include <dvs_screen_sim/event_simulator.h>
#include <dvs_screen_sim/screen_loop/gl_screen_renderer.h>
#include <dvs_screen_sim/screen_loop/grid_alignment.h>
#include <dvs_screen_sim/screen_loop/line_grid_check.h>
#include <dvs_screen_sim/screen_loop/projection_pipeline.h>
#include <dvs_screen_sim/screen_loop/emulated_screen_loop.h>
#include <dvs_screen_sim/screen_loop/virtual_monitor.h>
#include <dvs_screen_sim/trajectory.h>

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

using namespace dvs_screen_sim;
using namespace dvs_screen_sim::screen_loop;

namespace
{
/// Bounding box of the pixels brighter than 0.5.
bool brightBox(const std::vector<float>& grey, int w, int h, Eigen::Vector2d& lo, Eigen::Vector2d& hi)
{
  lo = Eigen::Vector2d(w, h);
  hi = Eigen::Vector2d(-1, -1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (grey[static_cast<size_t>(y) * w + x] > 0.5f)
      {
        lo = lo.cwiseMin(Eigen::Vector2d(x, y));
        hi = hi.cwiseMax(Eigen::Vector2d(x + 1, y + 1));  // pixel x covers [x, x+1)
      }
  return hi.x() >= 0;
}
}  // namespace

TEST(GlScreenRenderer, DrawsThePipelineAndReadsItBack)
{
  WindowConfig wc;
  wc.fullscreen = false;
  wc.width = 320;
  wc.height = 240;
  GlScreenRenderer gl(wc);
  ASSERT_EQ(gl.width(), 320);
  const auto cam = dvs_calibration::CameraModel::dvs128();
  ProjectionPipeline pipe(cam);
  const Pose T = Pose::fromWorldCamera(lookingAtWallOrientation(), Eigen::Vector3d(0.0, 0.0, 2.0));
  Scene scene = defaultSquareScene(0.6, 1.0, 0.0);  // white 0.6 m square on black
  scene.finalize();
  std::vector<float> grey;
  for (int corrected = 0; corrected < 2; ++corrected)
  {
    Eigen::Matrix3d H;
    H << 0.8, 0.0, 0.1, 0.0, 0.9, -0.05, 0.0, 0.0, 1.0;
    pipe.setCorrection(corrected ? H : Eigen::Matrix3d::Identity());
    gl.clear(0.0);
    gl.setMatrices(pipe.correctedProjection(), viewMatrix(T));
    gl.drawScenePolygons(scene, 0.0);
    gl.readBackBuffer(grey);
    gl.swap();
    ASSERT_EQ(grey.size(), 320u * 240u);
    Eigen::Vector2d lo, hi;
    ASSERT_TRUE(brightBox(grey, 320, 240, lo, hi));
    // Expected: the square's corners through the same pipeline, in window pixels.
    Eigen::Vector2d elo(1e9, 1e9), ehi(-1e9, -1e9);
    for (const auto& v : scene.polygons[0].vertices)
    {
      Eigen::Vector2d vp;
      ASSERT_TRUE(pipe.viewport(T, Eigen::Vector3d(v.x(), v.y(), 0.0), vp));
      const Eigen::Vector2d w = viewportToWindow(vp, 320, 240);
      elo = elo.cwiseMin(w);
      ehi = ehi.cwiseMax(w);
    }
    EXPECT_NEAR(lo.x(), elo.x(), 1.0) << "corrected " << corrected;
    EXPECT_NEAR(lo.y(), elo.y(), 1.0);
    EXPECT_NEAR(hi.x(), ehi.x(), 1.0);
    EXPECT_NEAR(hi.y(), ehi.y(), 1.0);
    // The white square is white, the rest black.
    EXPECT_NEAR(grey[static_cast<size_t>(120) * 320 + 160], corrected ? grey[static_cast<size_t>(120) * 320 + 160] : 1.0f, 1e-6);
  }
  // Viewport discs: centred where asked.
  gl.clear(0.0);
  gl.drawViewportDiscs({Eigen::Vector2d(0.5, -0.5)}, 10.0, 1.0);
  gl.readBackBuffer(grey);
  gl.swap();
  Eigen::Vector2d lo, hi;
  ASSERT_TRUE(brightBox(grey, 320, 240, lo, hi));
  const Eigen::Vector2d c = viewportToWindow({0.5, -0.5}, 320, 240);
  EXPECT_NEAR(0.5 * (lo.x() + hi.x()), c.x(), 0.6);
  EXPECT_NEAR(0.5 * (lo.y() + hi.y()), c.y(), 0.6);
  EXPECT_NEAR(hi.x() - lo.x(), 20.0, 1.5);
}

namespace
{
struct HilRun
{
  GridAlignment alignment;
  LineDistanceStats corrected, uncorrected, reference;
};

HilRun runHil(const Pose& T_wall_dvs, uint64_t seed)
{
  HilRun out;
  WindowConfig wc;
  wc.fullscreen = false;
  wc.width = 1024;
  wc.height = 768;
  GlScreenRenderer gl(wc);

  EmulationConfig ec;
  ec.camera = dvs_calibration::CameraModel::dvs128();
  ec.T_wall_dvs = T_wall_dvs;
  ec.monitor.pixel_pitch = 0.0006;  // 1024 x 768 px = 0.61 m x 0.46 m
  ec.monitor.top_left = {-0.5 * 1024 * ec.monitor.pixel_pitch, 0.5 * 768 * ec.monitor.pixel_pitch};
  ec.monitor.black_level = 0.02;
  ec.monitor.white_level = 0.9;
  ec.pattern.cols = 7;
  ec.pattern.rows = 5;
  ec.pattern.spacing_vp = {0.085, 0.11};
  ec.pattern.radius_px = 11;
  ec.model.noise = noisePreset("realistic");
  ec.seed = seed;
  EmulatedScreenLoop loop(ec, gl);

  // Phase 1: alignment (blinking circles, 6 refreshes ~ 100 ms as the thesis's windows).
  out.alignment = loop.align();
  if (!out.alignment.ok)
    return out;

  // Phase 2: the blinking line grid, corrected then uncorrected, 6 refreshes each.
  const Pose T_world_virtual = Pose::fromWorldCamera(orientationFromYawPitchRollDeg({4, -3, 8}), Eigen::Vector3d(0.03, -0.02, 1.0));
  const auto lines = lineGrid(7, 7, 0.12);
  const double width = 0.003;
  const auto expected = expectedImageLines(ec.camera, T_world_virtual, lines);
  out.corrected = eventLineDistances(loop.showLines(T_world_virtual, lines, width, true, 7), ec.camera, expected);
  out.uncorrected = eventLineDistances(loop.showLines(T_world_virtual, lines, width, false, 7), ec.camera, expected);

  // The pure-software reference: the same DVS at the virtual camera's pose looking at the same
  // blinking grid directly (no screen): the floor of the per-event distance (pixel spread).
  out.reference = referenceLineGridDistances(ec, T_world_virtual, 7, 7, 0.12, width, 7);
  return out;
}
}  // namespace

void checkScreenInTheLoop(const Eigen::Vector3d& ypr_deg, const Eigen::Vector3d& aim, double distance, uint64_t seed)
{
  const HilRun r = runHil(EmulationConfig::dvsPoseAimedAt(ypr_deg, aim.head<2>(), distance), seed);
  ASSERT_TRUE(r.alignment.ok) << r.alignment.reason;
  std::printf("alignment: H_D residual rms %.3f px, mean %.3f px (35 circles)\n",
              r.alignment.result.residual_dvs_px.rms, r.alignment.result.residual_dvs_px.mean);
  std::printf("corrected line grid: %zu/%zu events within 2 px, mean event distance %.3f px, mean line offset %.3f px "
              "(%zu pieces)\n",
              r.corrected.events_used, r.corrected.events_total, r.corrected.mean_event_distance,
              r.corrected.mean_line_offset, r.corrected.chunks);
  std::printf("uncorrected line grid: %zu/%zu events within 2 px, mean event distance %.3f px, mean line offset %.3f px\n",
              r.uncorrected.events_used, r.uncorrected.events_total, r.uncorrected.mean_event_distance,
              r.uncorrected.mean_line_offset);
  std::printf("pure-software reference: %zu/%zu events within 2 px, mean event distance %.3f px, mean line offset "
              "%.3f px\n",
              r.reference.events_used, r.reference.events_total, r.reference.mean_event_distance,
              r.reference.mean_line_offset);
  EXPECT_LT(r.alignment.result.residual_dvs_px.rms, 0.3);
  // The per-event distance is the pure-software DVS's own (pixel spread) plus little.
  EXPECT_LT(r.corrected.mean_event_distance, r.reference.mean_event_distance + 0.1);
  EXPECT_GT(r.corrected.events_used, 0.9 * r.corrected.events_total);
  EXPECT_GT(r.corrected.chunks, 40u);
  EXPECT_LE(r.corrected.mean_line_offset, 0.2);
  // Without the correction the lines are elsewhere.
  EXPECT_LT(r.uncorrected.events_used, 0.6 * r.uncorrected.events_total);
}

// The DVS 0.22 m in front of the screen, yaw 15 deg, pitch -12 deg, roll 4 deg, shifted.
TEST(ScreenInTheLoop, AlignmentFromEventsMakesTheLineGridFallOnTheExpectedLines)
{
  checkScreenInTheLoop({15, -12, 4}, {0.015, -0.01, 0.0}, 0.22, 1);
}

// Tilted 20 deg the other way (yaw -20, pitch 8, roll -6), shifted the other way.
TEST(ScreenInTheLoop, AlignmentWorksForAStrongerOppositeTilt)
{
  checkScreenInTheLoop({-20, 8, -6}, {-0.02, 0.015, 0.0}, 0.22, 2);
}

// Playback: the scene along a trajectory, slowed down 4x on the screen; the events come back in
// trajectory time and lie on the square's edges as the virtual camera saw them at that time.
TEST(ScreenInTheLoop, PlaybackEventsAreInTrajectoryTimeOnTheProjectedEdges)
{
  WindowConfig wc;
  wc.fullscreen = false;
  wc.width = 1024;
  wc.height = 768;
  GlScreenRenderer gl(wc);
  EmulationConfig ec;
  ec.camera = dvs_calibration::CameraModel::dvs128();
  ec.T_wall_dvs = EmulationConfig::dvsPoseAimedAt({15, -12, 4}, {0.015, -0.01}, 0.22);
  ec.monitor.pixel_pitch = 0.0006;
  ec.monitor.top_left = {-0.5 * 1024 * ec.monitor.pixel_pitch, 0.5 * 768 * ec.monitor.pixel_pitch};
  ec.monitor.black_level = 0.02;
  ec.monitor.white_level = 0.9;
  ec.pattern.spacing_vp = {0.085, 0.11};
  ec.pattern.radius_px = 11;
  ec.monitor.response_time = 0.002;
  EmulatedScreenLoop loop(ec, gl);
  ASSERT_TRUE(loop.align().ok);

  Scene scene = defaultSquareScene();
  scene.finalize();
  LinearTrajectoryParams lp;
  lp.start_position = {-0.1, 0.0, 1.5};
  lp.end_position = {0.1, 0.05, 1.6};
  lp.start_ypr_deg = {0, 0, 0};
  lp.end_ypr_deg = {3, -2, 20};
  lp.duration = 0.3;
  LinearTrajectory trajectory(lp);
  const double duration = 0.3;
  dvs_calibration::Trajectory shown;
  const dvs_driver::EventVector events = loop.playTrajectory(scene, trajectory, duration, TimeScale{4.0}, &shown);
  ASSERT_GT(events.size(), 2000u);
  // One displayed pose per refresh, each the trajectory's pose at the centre of its display
  // interval (refresh period / time scale of trajectory time), stamped half the monitor's
  // response time later (when its light is half-way).
  const double hold = ec.refresh_period / 4.0;
  const double seen_delay = 0.5 * ec.monitor.response_time / 4.0;
  ASSERT_NEAR(static_cast<double>(shown.size()), duration / hold, 1.5);
  for (size_t i = 0; i < shown.size(); ++i)
  {
    const double centre = (static_cast<double>(i) + 0.5) * hold;
    ASSERT_NEAR(shown[i].t, centre + seen_delay, 1e-9) << "frame " << i;
    EXPECT_LT((shown[i].T_world_camera.p_world_camera() - trajectory.poseAt(centre).p_world_camera()).norm(), 1e-12);
  }
  size_t near = 0;
  for (const auto& e : events)
  {
    ASSERT_GE(e.t_ns, 0);
    ASSERT_LE(e.t_ns, static_cast<int64_t>(duration * 1e9) + 1000000);
    const Pose T = trajectory.poseAt(e.t_ns * 1e-9);
    const Eigen::Vector2f uf = ec.camera.undistortedPixelLut(e.x, e.y);
    const Eigen::Vector2d p(uf.x(), uf.y());
    const auto& v = scene.polygons[0].vertices;
    double best = 1e9;
    for (size_t i = 0; i < v.size(); ++i)
    {
      Eigen::Vector2d a, b;
      ec.camera.projectIdeal(T.toCamera({v[i].x(), v[i].y(), 0.0}), a);
      ec.camera.projectIdeal(T.toCamera({v[(i + 1) % v.size()].x(), v[(i + 1) % v.size()].y(), 0.0}), b);
      const Eigen::Vector2d d = b - a;
      const double u = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      best = std::min(best, (p - (a + u * d)).norm());
    }
    if (best <= 1.0)
      ++near;
  }
  std::printf("playback: %zu events, %.1f %% within 1 px of the square's edges at their (trajectory) time\n",
              events.size(), 100.0 * near / events.size());
  EXPECT_GT(static_cast<double>(near) / events.size(), 0.95);
}

int main(int argc, char** argv)
{
  if (!reexecUnderXvfbIfNoDisplay(argc, argv))
    return 1;
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
