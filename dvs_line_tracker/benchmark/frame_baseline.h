#pragma once
// The practitioner's baseline (benchmark only, not part of the product): accumulate the events
// of a frame period into an image, detect the square from scratch in every frame (Hough lines,
// polygon, corners), solve PnP, one pose per frame. Corner identity comes from continuity (the
// previous frame's image-up direction serves as the "up" hint). No per-event tracking.
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/event.h>
#include <dvs_line_tracker/hough_line_detector.h>
#include <dvs_line_tracker/line_map.h>
#include <dvs_line_tracker/polygon_search.h>
#include <dvs_line_tracker/pose_initializer.h>
#include <dvs_calibration/trajectory_accuracy.h>

#include <chrono>
#include <vector>

namespace dvs_line_tracker
{
struct FrameBaselineResult
{
  dvs_calibration::Trajectory poses;    ///< stamped with the frame's end time
  std::vector<double> frame_cpu_s;   ///< processing time per frame
  int frames = 0, frames_with_pose = 0;
};

/// Each frame holds the events of its period, and at least the latest `min_events` (sparse
/// scenes would otherwise give empty frames).
inline FrameBaselineResult runFrameBaseline(const dvs_driver::EventVector& events,
                                            const dvs_calibration::CameraModel& camera, const LineMap& map,
                                            double frame_period_s, int min_events = 1500)
{
  FrameBaselineResult result;
  if (events.empty())
    return result;
  const auto& in = camera.intrinsics();
  const PinholeK k{in.fx, in.fy, in.cx, in.cy};
  HoughParams hp;
  hp.neighbour_filter = false;
  hp.window_events = 1 << 20;
  HoughLineDetector hough(camera.width(), camera.height(), hp);
  const int64_t period_ns = static_cast<int64_t>(frame_period_s * 1e9);
  size_t i = 0, first_of_period = 0;
  for (int64_t t_end = events.front().t_ns + period_ns; i < events.size(); t_end += period_ns)
  {
    while (i < events.size() && events[i].t_ns < t_end)
      ++i;
    const auto t0 = std::chrono::steady_clock::now();
    const size_t first = i > static_cast<size_t>(min_events) ? std::min(i - min_events, first_of_period) : 0;
    first_of_period = i;
    hough.reset();
    for (size_t j = first; j < i; ++j)
    {
      const auto& e = events[j];
      if (!camera.inSensor(e.x, e.y))
        continue;
      const Eigen::Vector2f p = camera.undistortedPixelLut(e.x, e.y);
      hough.addEvent(p.x(), p.y(), e.x, e.y, e.t_ns);
    }
    ++result.frames;
    LineMap continuity = map;
    if (!result.poses.empty())
      continuity.up_world = result.poses.back().T_world_camera.R_world_camera() * Eigen::Vector3d(0, -1, 0);
    for (const auto& poly : findPolygons(hough.detectSegments(), 4, PolygonSearchParams(), 4))
    {
      InitialPose init;
      if (estimateInitialPose(poly.corners, continuity, k, PoseInitParams(), init))
      {
        result.poses.push_back({t_end * 1e-9, init.pose});
        ++result.frames_with_pose;
        break;
      }
    }
    result.frame_cpu_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return result;
}
}  // namespace dvs_line_tracker
