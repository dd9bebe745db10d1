// The screen-in-the-loop procedure (the code the screen_loop node and the emulation both run) on
// fakes: a screen that records what is drawn and shows frames on a simulated clock, and an event
// source with a known clock offset that hands out scripted events. No OpenGL, no display.
#include <dvs_screen_sim/screen_loop/live_event_collector.h>
#include <dvs_screen_sim/screen_loop/screen_loop_procedure.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace dvs_screen_sim;
using namespace dvs_screen_sim::screen_loop;

namespace
{
/// Records the drawing calls of the current frame.
struct RecordingCanvas : ScreenCanvas
{
  int width() const override { return 1024; }
  int height() const override { return 768; }
  void clear(double intensity) override { clears.push_back(intensity); }
  void setMatrices(const Eigen::Matrix4d&, const Eigen::Matrix4d& v) override { views.push_back(v); }
  void drawScenePolygons(const Scene&, double t) override { scene_times.push_back(t); }
  void drawWorldLines(const std::vector<WorldLine>& lines, double, double) override { line_draws += lines.size() > 0; }
  void drawViewportDiscs(const Points2d& centres, double, double, int) override { disc_draws.push_back(centres.size()); }

  std::vector<double> clears, scene_times;
  std::vector<Eigen::Matrix4d> views;
  std::vector<size_t> disc_draws;
  int line_draws = 0;
};

/// Frames every `period` seconds on a simulated screen clock starting at 100 s; the first frame
/// of a call is the next refresh.
struct FakeScreen : LoopScreen
{
  ScreenCanvas& canvas() override { return canvas_; }
  double refreshPeriod() const override { return period; }
  bool showFrames(double duration, const DrawFrame& draw, const FrameShown& shown) override
  {
    ++calls;
    const int64_t first = next_frame;
    for (int64_t k = 0; k * period <= duration + 1e-12; ++k)
    {
      Frame f;
      f.index = first + k;
      f.k = k;
      f.t = static_cast<double>(k) * period;
      f.start_ns = static_cast<int64_t>(std::llround((100.0 + static_cast<double>(first + k) * period) * 1e9));
      draw(f, canvas_);
      if (shown)
        shown(f, f.start_ns);
      if (on_frame)
        on_frame(f);
      next_frame = first + k + 1;
    }
    return true;
  }

  double period = 0.02;
  int64_t next_frame = 0;
  int calls = 0;
  std::function<void(const Frame&)> on_frame;
  RecordingCanvas canvas_;
};

/// DVS time = screen time + offset; keeps the events it is given (as if they had arrived).
struct FakeEvents : LoopEventSource
{
  int64_t dvsTimeNs(int64_t screen_ns) const override { return screen_ns + offset_ns; }
  bool clockValid() const override { return true; }
  void keepFrom(int64_t from) override
  {
    keeping = true;
    from_ns = from;
    kept.clear();
    keep_calls.push_back(from);
  }
  void drain() override { ++drains; }
  dvs_driver::EventVector takeKept() override
  {
    keeping = false;
    dvs_driver::EventVector out;
    out.swap(kept);
    return out;
  }
  void arrive(const dvs_driver::Event& e)
  {
    if (keeping && e.t_ns >= from_ns)
      kept.push_back(e);
  }

  int64_t offset_ns = -99'000'000'000;  // the DVS's clock started 99 s after the host's origin
  bool keeping = false;
  int64_t from_ns = 0;
  dvs_driver::EventVector kept;
  std::vector<int64_t> keep_calls;
  int drains = 0;
};

ProcedureConfig config()
{
  ProcedureConfig c;
  c.pattern.cols = 7;
  c.pattern.rows = 5;
  c.pattern.spacing_vp = {0.085, 0.11};
  c.pattern.radius_px = 11;
  c.alignment_settle = 0.1;
  c.alignment_duration = 0.2;
  c.alignment_attempts = 3;
  c.response_time = 0.004;
  c.settle_frames = 1;
  return c;
}
}  // namespace

TEST(ScreenLoopProcedure, AlignmentRetriesAndReportsWhenTheGridIsNotSeen)
{
  FakeScreen screen;
  FakeEvents events;
  std::vector<std::string> warnings, errors;
  ScreenLoopProcedure procedure(config(), dvs_calibration::CameraModel::dvs128(), screen, events,
                                [&](LogLevel level, const std::string& m) {
                                  if (level == LogLevel::Warn)
                                    warnings.push_back(m);
                                  if (level == LogLevel::Error)
                                    errors.push_back(m);
                                });
  const GridAlignment a = procedure.align();
  EXPECT_FALSE(a.ok);
  EXPECT_FALSE(a.reason.empty());
  EXPECT_EQ(screen.calls, 3);  // every attempt
  EXPECT_EQ(warnings.size(), 3u);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("3 attempts"), std::string::npos);
  // Per attempt: 0.3 s of 20 ms frames (16, both ends included); the events count from the
  // first frame at or after the 0.1 s settling (frame 5 of the attempt), in the DVS's clock.
  ASSERT_EQ(events.keep_calls.size(), 3u);
  EXPECT_EQ(events.keep_calls[0], std::llround((100.0 + 5 * 0.02) * 1e9) + events.offset_ns);
  EXPECT_EQ(screen.next_frame, 3 * 16);
  // The grid blinks with the screen's frame counter: on for blink_frames refreshes, off as long.
  ASSERT_EQ(screen.canvas_.clears.size(), 48u);
  EXPECT_EQ(screen.canvas_.disc_draws.size(), 24u);
  EXPECT_EQ(screen.canvas_.disc_draws.front(), 35u);
  // Nothing was corrected.
  EXPECT_TRUE(procedure.pipeline().correction().isIdentity());
}

TEST(ScreenLoopProcedure, PlaybackShowsCentredPosesAndRescalesToTrajectoryTime)
{
  FakeScreen screen;
  FakeEvents events;
  ScreenLoopProcedure procedure(config(), dvs_calibration::CameraModel::dvs128(), screen, events);
  LinearTrajectoryParams lp;
  lp.duration = 0.1;
  const LinearTrajectory trajectory(lp);
  Scene scene = defaultSquareScene();
  scene.finalize();
  const TimeScale scale{4.0};
  // Events "arrive" during the playback: one per frame at the frame's DVS time + 1 ms, and one
  // stamped before the playback's start (must be dropped).
  screen.on_frame = [&](const Frame& f) {
    events.arrive({events.dvsTimeNs(f.start_ns) + 1000000, 1, 2, true});
    events.arrive({events.dvsTimeNs(f.start_ns) - 30000000, 3, 4, false});
  };
  std::vector<StampedPose> live;
  const Playback p =
      procedure.play(scene, trajectory, 0.1, scale, [&](const StampedPose& sp) { live.push_back(sp); });
  ASSERT_TRUE(p.completed);
  EXPECT_EQ(events.drains, 1);
  // 1 settling frame (the start pose) + the playback: 0.4 s of screen time, 21 frames.
  const double hold = 0.02;
  ASSERT_EQ(p.shown.size(), 21u);
  ASSERT_EQ(live.size(), 21u);
  ASSERT_EQ(screen.canvas_.scene_times.size(), 22u);
  EXPECT_EQ(screen.canvas_.scene_times[0], 0.0);
  const int64_t start_screen_ns = std::llround((100.0 + 1 * hold) * 1e9);
  EXPECT_EQ(p.start_dvs_ns, start_screen_ns + events.offset_ns);
  for (size_t i = 0; i < p.shown.size(); ++i)
  {
    // Frame i shows the pose at the centre of its display interval (trajectory time) ...
    const double centre = (static_cast<double>(i) + 0.5) * hold / scale.factor;
    EXPECT_NEAR(screen.canvas_.scene_times[i + 1], centre, 1e-12);
    EXPECT_LT((p.shown[i].T_world_camera.p_world_camera() - trajectory.poseAt(centre).p_world_camera()).norm(), 1e-12);
    // ... stamped when the DVS sees it: half a refresh and half the response time after it is
    // shown (rescaled to trajectory time; live in the DVS's own clock).
    EXPECT_NEAR(p.shown[i].t, centre + 0.5 * 0.004 / scale.factor, 1e-9);
    const double live_expected = (start_screen_ns + events.offset_ns) * 1e-9 + i * hold + 0.5 * hold + 0.002;
    EXPECT_NEAR(live[i].t, live_expected, 1e-6);
    EXPECT_NEAR(screen.canvas_.views[i + 1](2, 3), viewMatrix(trajectory.poseAt(centre))(2, 3), 1e-12);
  }
  // Events: those stamped from the start on, rescaled to trajectory time (screen time / 4).
  // 21 (1 ms after each playback frame) + 19 (30 ms before the playback frames 2..20: those at
  // or after the start; before it, dropped).
  ASSERT_EQ(p.events.size(), 21u + 19u);
  for (const auto& e : p.events)
    EXPECT_GE(e.t_ns, 0);
  EXPECT_EQ(p.events.front().t_ns, 250000);  // 1 ms of screen time after the start / 4
}

TEST(ScreenLoopProcedure, RefusesABadConfigurationNamingTheField)
{
  FakeScreen screen;
  FakeEvents events;
  ProcedureConfig c = config();
  c.alignment_attempts = 0;
  try
  {
    ScreenLoopProcedure procedure(c, dvs_calibration::CameraModel::dvs128(), screen, events);
    FAIL() << "accepted alignment_attempts = 0";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_NE(std::string(e.what()).find("alignment_attempts"), std::string::npos);
  }
}

// The node's event source: the DVS clock from the packets, and the events arriving while kept
// (late packets included: a live sensor's window is what arrives).
TEST(LiveEventCollector, LearnsTheClockAndKeepsWhatArrives)
{
  LiveEventCollector c;
  EXPECT_FALSE(c.clockValid());
  const dvs_driver::Event a[] = {{1000, 1, 1, true}, {2000, 2, 2, false}};
  c.addPacket(a, a + 2, 5000);  // arrived 3 us after its last event: offset <= -3000
  EXPECT_TRUE(c.clockValid());
  EXPECT_EQ(c.dvsTimeNs(10000), 7000);
  const dvs_driver::Event b[] = {{4000, 3, 3, true}};
  c.addPacket(b, b + 1, 5500);  // less delayed: offset -1500
  EXPECT_EQ(c.dvsTimeNs(10000), 8500);
  EXPECT_TRUE(c.takeKept().empty());  // nothing kept before keepFrom
  c.keepFrom(c.dvsTimeNs(6000));
  const dvs_driver::Event late[] = {{3000, 4, 4, true}, {6000, 5, 5, false}};
  c.addPacket(late, late + 2, 9000);
  const auto kept = c.takeKept();
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].t_ns, 3000);
  c.addPacket(late, late + 2, 9500);
  EXPECT_TRUE(c.takeKept().empty());  // not keeping any more
  EXPECT_EQ(c.packets(), 4u);
}
