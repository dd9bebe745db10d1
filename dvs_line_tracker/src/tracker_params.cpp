#include <dvs_line_tracker/tracker_params.h>
#include <dvs_line_tracker/body_odometry.h>

#include <dvs_calibration/camera_model.h>

#include <yaml-cpp/yaml.h>

#include <stdexcept>

namespace dvs_line_tracker
{
namespace
{
constexpr double kInf = 1e308;
}  // namespace

dvs_driver::ParamTable trackerParamTable(LineTrackerParams& p, std::string& solver_name)
{
  dvs_driver::ParamTable t("dvs_line_tracker");
  auto positive = [&](const char* name, double& v, const char* unit, double max, const char* doc) {
    t.add(name, v, unit, 0, max, doc).min_exclusive = true;
  };
  // Initialisation (thesis 4.2.1).
  t.add("hough_angle_bin_deg", p.hough.angle_bin_deg, "deg", 0.1, 90, "Hough angle bin (thesis 7.5)");
  t.add("hough_radius_bin_px", p.hough.radius_bin_px, "px", 0.1, 100, "Hough radius bin (thesis 2.5)");
  t.add("hough_threshold", p.hough.vote_threshold, "events", 1, 1000000, "votes for a line candidate");
  positive("hough_attribution_distance_px", p.hough.attribution_distance_px, "px", kInf,
           "events this close belong to a candidate line; the initialiser's refinement and validation attribute the "
           "window's events at this distance too");
  positive("segment_max_gap_px", p.hough.max_gap_px, "px", kInf, "a larger gap splits a segment");
  positive("segment_min_length_px", p.hough.min_segment_length_px, "px", kInf, "shorter segments are dropped");
  t.add("segment_min_events", p.hough.min_segment_events, "events", 1, 1000000, "segments with fewer are dropped");
  t.add("init_window_events", p.hough.window_events, "events", 1, 10000000, "latest events voting in the Hough space");
  t.add("init_unique_pixels", p.hough.unique_pixels, "a pixel already in the window does not vote again");
  t.add("hough_remove_found_votes", p.hough.remove_found_votes,
        "progressive Hough: a found segment's events stop voting for the rest of the detection");
  t.add("init_full_hough_fallback", p.init_full_hough_fallback,
        "when the progressive Hough's segments give no pose, the same attempt tries the full Hough on each angle's radius peaks");
  t.add("init_neighbour_filter", p.hough.neighbour_filter, "vote only for events with neighbours that fired shortly before");
  t.add("init_neighbour_filter_events", p.hough.neighbour_filter_events, "events", 1, 10000000,
        "'shortly before': among this many latest events");
  t.add("init_neighbour_filter_min", p.hough.neighbour_filter_min, "pixels", 1, 8, "neighbours that must have fired");
  t.add("init_neighbour_same_polarity", p.hough.neighbour_same_polarity,
        "only neighbours whose latest event had the event's polarity count (slow scenes in heavy background "
        "activity; with init_neighbour_filter_events 1500, see the tracker's BENCHMARKS.md)");
  t.add("init_scale_with_sensor", p.init_scale_with_sensor,
        "event counts and gaps of the initialisation are for 128x128; scaled by sqrt(pixels)/128 on larger sensors "
        "(the neighbour filter's horizon by pixels/128^2)");
  t.add("init_evidence_windows", p.init_evidence_windows, "", 1, 100,
        "side coverage is validated on this many Hough windows of the latest voted events");
  t.add("init_max_event_age", p.hough.max_event_age_s, "s", 0, 1e6,
        "voted events this much older than the latest stop voting and are no longer evidence (0: no limit): "
        "a slow scene's window otherwise still holds what the camera saw seconds before");
  t.add("reacquire_prior", p.reacquire_prior_s, "s", 0, 3600,
        "after a loss, the last tracked pose is tried first for this long (0: off)");
  t.add("reacquire_capture_px", p.reacquire_capture_px, "px", 0, 1000,
        "the prior is refined on the window events this close to its projected map first, then half as close, "
        "down to hough_attribution_distance_px (0: only at that distance)");
  t.add("max_event_gap", p.max_event_gap_s, "s", 0, 3600,
        "a longer gap between events makes the pose stale (lost, re-acquired) or, with a healthy IMU, is bridged by it (0: off)");
  t.add("init_check_interval", p.init_check_interval, "events", 1, 10000000, "voted events between detection attempts");
  t.add("init_min_check_period", p.init_min_check_period_s, "s", 0, 10, "and at least this much event time between attempts");
  t.add("init_min_events", p.init_min_events, "events", 0, 10000000, "voted events before the first attempt");
  t.add("init_refine_events", p.init_refine_events, "events", 0, 10000000,
        "latest window events refining the initial pose (0: no refinement)");
  t.add("init_catch_up", p.init_catch_up,
        "when tracking starts, the events since the oldest one the initial pose was refined on go through the per-event "
        "update at once: the first pose is that of the latest event, not of the refinement window's middle");
  t.add("init_min_coverage", p.init_min_coverage, "", 0, 1, "each visible side this much covered by window events");
  t.add("init_border_margin_px", p.init_border_margin_px, "px", 0, 100, "segments and corners this close to the border are ignored");
  t.add("init_max_inside_ratio", p.init_max_inside_ratio, "", 0, kInf, "events inside the polygon / events on its sides, at most");
  t.add("init_max_surrounding_coverage", p.init_max_surrounding_coverage, "", 0, 1,
        "covered fraction of the strips beside the sides (3 attribution distances away, each side's quieter one), "
        "at most; 1: no limit");
  t.add("init_min_explained", p.init_min_explained, "", 0, 1,
        "fraction of the Hough window's events the initial pose must explain (within the attribution distance of a "
        "projected map side); open polygons and maps of several polygons need at least 0.5");
  t.add("init_max_view_angle_deg", p.init_max_view_angle_deg, "deg", 0, 90,
        "the initial pose sees its polygon at most this far off the polygon's normal (90: no limit; tracking goes on "
        "beyond it)");
  t.add("init_confirmations", p.init_confirmations, "", 0, 4, "earlier agreeing detections (of the last 4) needed");
  positive("init_confirm_position_ratio", p.init_confirm_position_ratio, "", kInf, "agreement: position difference / distance");
  positive("init_confirm_angle_deg", p.init_confirm_angle_deg, "deg", 180, "agreement: orientation difference");
  t.add("init_min_up_margin", p.init_min_up_margin, "", 0, 2,
        "a symmetric polygon's pose must be this much more upright (cosine) than its rotations that fit");
  positive("init_max_roll_rate", p.init_max_roll_rate_deg_s, "deg/s", kInf,
           "and the camera must roll slower than this between the confirming detections (the map's up assumes near upright)");
  t.add("polygon_min_angle_deg", p.polygon.min_turn_angle_deg, "deg", 0, 180, "turn between neighbouring sides, at least");
  t.add("polygon_max_angle_deg", p.polygon.max_turn_angle_deg, "deg", 0, 180, "turn between neighbouring sides, at most");
  t.add("polygon_wide_min_angle_deg", p.polygon_wide_min_angle_deg, "deg", 0, 180,
        "when no polygon within the turn bounds above starts tracking, polygons turning down to this are tried too (steep views, wide lenses)");
  t.add("polygon_wide_max_angle_deg", p.polygon_wide_max_angle_deg, "deg", 0, 180,
        "and up to this (equal to the bounds above: off)");
  positive("polygon_corner_proximity_ratio", p.polygon.corner_proximity_ratio, "", kInf,
           "side end to corner, at most this fraction of the two sides' summed lengths");
  positive("polygon_min_side_px", p.polygon.min_side_px, "px", kInf, "shortest accepted side");
  positive("init_max_reprojection_px", p.init.max_reprojection_rms_px, "px", kInf, "corner reprojection RMS, at most");
  t.add("init_refine", p.init.refine, "Ceres refinement of the corners' reprojection error");
  // Tracking (thesis 4.2.2).
  positive("max_orthogonal_distance_px", p.attribution.max_orthogonal_px, "px", kInf, "attribution distance of an event to a segment while tracking (thesis 2)");
  t.add("max_parallel_distance_px", p.attribution.max_parallel_px, "px", 0, kInf, "beyond a segment's ends (thesis 10)");
  t.add("edge_run_model", p.edge_run_model, "place events where the pixel's integrated log level puts the edge");
  t.add("contrast_threshold", p.contrast_threshold, "log intensity", 0, 2, "the sensor's C (0: learned)");
  t.add("contrast_threshold_prior", p.contrast_threshold_prior, "log intensity", 0, 2,
        "C until it is learned (0: the constant offset until then)");
  t.add("contrast_learning_runs", p.contrast_learning_runs, "runs", 1, 100000000, "completed runs before the learned C is used");
  t.add("edge_contrast_ratio", p.edge_contrast_ratio, "", 1, 1e6, "bright / dark intensity across the edges").min_exclusive = true;
  t.add("edge_offset_px", p.edge_offset_px, "px", 0, kInf, "constant offset towards the bright side (no run model)");
  t.add("buffer_motion_px", p.buffer_motion_px, "px", 0, kInf, "buffered events dropped once their segment moved this far (0: off)");
  t.add("buffer_size", p.buffer_size, "events", 2, 1024, "events per segment buffer (thesis 8)");
  t.add("solve_every_events", p.solve_every_events, "events", 1, 64,
        "the pose is solved once per this many attributed events (between: attributed and buffered; 1: every event)");
  t.add("solve_min_offset_px", p.solve_min_offset_px, "px", 0, kInf,
        "... and once the events since the last solve lie, summed, this far from their segments (0: every event)");
  t.add("max_solve_rate", p.max_solve_rate, "Hz", 0, 1e9,
        "... and at most this often per second of event time, 1 ms bursts let through (0: no limit)");
  t.add("factor_every_solves", p.factor_every_solves, "solves", 1, 1000,
        "the damped information is factored at most this many solves apart, its factor reused in between (1: every solve)");
  t.add("factor_information_change", p.factor_information_change, "", 0, 1,
        "... and once an element of its diagonal changed by this fraction, a segment turned (in)active or a quality check ran (0: every solve)");
  t.add("full_iterations", p.estimator.full_iterations, "", 1, 100, "Gauss-Newton iterations per event (solver full)");
  t.add("extra_relinearizations", p.estimator.extra_relinearizations, "", 0, 1000,
        "segments re-linearised round robin per solve, skipping one its own events re-linearised within the last n solves (n: map segments; solver incremental)");
  t.add("damping", p.estimator.damping, "", 0, kInf, "Marquardt damping, relative to the diagonal");
  t.add("damping_partial_view", p.damping_partial_view, "", 0, kInf, "damping while part of the map is out of view");
  t.add("damping_partial_view_rate", p.damping_partial_view_rate, "events/s", 0, 1e9,
        "below this attributed event rate the partial-view damping falls in proportion to it, down to `damping`: it holds the pose for a time, not for a number of events (0: off)");
  positive("huber_px", p.estimator.huber_px, "px", kInf, "Huber threshold of the residuals");
  t.add("solver", solver_name, {"incremental", "full"}, "one step per event on cached normal equations, or full Gauss-Newton");
  // Quality monitoring.
  t.add("quality_check_interval", p.quality_check_interval, "events", 1, 100000000, "events between quality checks");
  t.add("min_visible_segments", p.min_visible_segments, "", 2, 1000, "fewer visible segments: lost (6-DoF needs 3 lines)");
  t.add("min_visible_length_px", p.min_visible_length_px, "px", 0, kInf, "a segment is visible with this much inside the image");
  t.add("partial_view_grace_s", p.partial_view_grace_s, "s", 0, 10,
        "fewer than min_visible_segments visible, but two meeting at a corner (>= 30 deg), for up to this long: held, no pose reported, until a third side is back (0: lost at once)");
  positive("max_mean_residual_px", p.max_mean_residual_px, "px", kInf, "mean residual above this: lost");
  t.add("min_attributed_ratio", p.min_attributed_ratio, "", 0, 1, "attributed / all events below this: lost");
  t.add("min_unattributed_structure", p.min_unattributed_structure, "", 0, 1,
        "... and at least this share of the rest next to each other (structure, not noise): lost");
  t.add("loss_neighbour_events", p.loss_neighbour_events, "events", 1, 10000000,
        "'next to each other': two of the 8 neighbours fired among this many latest events (scaled by pixels as "
        "init_neighbour_filter_events)");
  t.add("attribution_drop_ratio", p.attribution_drop_ratio, "", 0, 1,
        "attributed share below this fraction of the track's level (>= 50 %), half the rest structure, residual >= 0.4 px: lost (0: off)");
  t.add("loss_silent_side_ratio", p.loss_silent_side_ratio, "", 0, 1,
        "a visible side that moved >= 1 px across the image (net, over 8 snapshots >= 10 ms apart) with fewer than this fraction of the events its polygon's densest side fired per swept px^2, while unexplained structure arrives near the polygon (its edge fires elsewhere), for 0.1 s: lost (0: off)");
  positive("min_depth", p.min_depth_m, "m", kInf,
           "the near plane: a map segment partly closer (or behind the camera) is clipped there and still tracked; one wholly closer: lost");
  t.add("max_time_backwards", p.max_time_backwards_s, "s", 0, kInf,
        "event time going back by more than this (a replayed bag) restarts the tracker");
  // IMU fusion (when an IMU stream is given).
  t.add("imu_q_camera_imu", p.imu.q_camera_imu, {}, "R_camera_imu as a quaternion 'x y z w' (IMU axes -> camera axes)");
  t.add("imu_p_camera_imu", p.imu.p_camera_imu, {}, "the IMU's origin in the camera frame 'x y z' [m]");
  t.add("imu_gravity_world", p.imu.gravity_world, {},
        "gravity in the map frame 'x y z' [m/s^2] when known (square on a wall, world y up: '0 -9.81 0'); empty: estimated");
  t.add("imu_time_offset", p.imu.time_offset_s, "s", -10, 10, "event time = IMU time + this");
  t.add("imu_gyro_noise_density", p.imu.gyro_noise_density, "rad/s/sqrt(Hz)", 0, 1, "gyroscope white noise").min_exclusive = true;
  t.add("imu_gyro_random_walk", p.imu.gyro_random_walk, "rad/s^2/sqrt(Hz)", 0, 1, "gyroscope bias random walk").min_exclusive = true;
  t.add("imu_accel_noise_density", p.imu.accel_noise_density, "m/s^2/sqrt(Hz)", 0, 10, "accelerometer white noise").min_exclusive = true;
  t.add("imu_accel_random_walk", p.imu.accel_random_walk, "m/s^3/sqrt(Hz)", 0, 10, "accelerometer bias random walk").min_exclusive = true;
  t.add("imu_initial_gyro_bias_sigma", p.imu.initial_gyro_bias_sigma, "rad/s", 0, 1, "prior 1-sigma of the gyroscope bias").min_exclusive = true;
  t.add("imu_initial_accel_bias_sigma", p.imu.initial_accel_bias_sigma, "m/s^2", 0, 10, "prior 1-sigma of the accelerometer bias").min_exclusive = true;
  t.add("imu_initial_velocity_sigma", p.imu.initial_velocity_sigma, "m/s", 0, 100, "velocity prior when tracking starts").min_exclusive = true;
  t.add("imu_initial_gravity_sigma", p.imu.initial_gravity_sigma, "m/s^2", 0, 10, "prior of an estimated gravity, per axis").min_exclusive = true;
  t.add("imu_gravity_check", p.imu.gravity_check_s, "s", 0, 60,
        "an estimated gravity is checked this long (accelerometer bias plausible) before the accelerometer moves the pose");
  t.add("imu_update_period", p.imu.update_period_s, "s", 1e-5, 1, "the vision pose corrects the filter this often");
  t.add("imu_vision_covariance_scale", p.imu.vision_covariance_scale, "", 0, 1e9,
        "the vision's covariance is this x its Gauss-Newton estimate (overlapping buffers, errors not white)").min_exclusive = true;
  t.add("imu_vision_error_scale", p.imu.vision_error_scale, "", 0, 1e9,
        "the reported pose covariance adds this x the Gauss-Newton estimate: the vision's slowly varying error, which the filter cannot average away");
  t.add("imu_max_latency", p.imu.max_latency_s, "s", 0, 10, "newest IMU sample older than this at an event: late or missing, vision alone").min_exclusive = true;
  t.add("imu_max_gyro", p.imu.max_gyro_rad_s, "rad/s", 0, 1e4, "a larger rate is absurd (deg/s given as rad/s?)").min_exclusive = true;
  t.add("imu_max_accel", p.imu.max_accel_m_s2, "m/s^2", 0, 1e5, "a larger specific force is absurd").min_exclusive = true;
  t.add("imu_max_bridge", p.imu.max_bridge_s, "s", 0, 60, "event-free gaps up to this long are bridged by the IMU alone");
  t.addRule([&p]() -> std::string {
    ImuExtrinsics x;
    return parseImuExtrinsics(p.imu, x);
  });
  // Rules across parameters.
  t.addRule([&p]() -> std::string {
    return p.polygon.min_turn_angle_deg < p.polygon.max_turn_angle_deg
               ? ""
               : "polygon_min_angle_deg must be < polygon_max_angle_deg";
  });
  t.addRule([&p]() -> std::string {
    return p.polygon_wide_min_angle_deg <= p.polygon.min_turn_angle_deg &&
                   p.polygon_wide_max_angle_deg >= p.polygon.max_turn_angle_deg
               ? ""
               : "polygon_wide_min_angle_deg must be <= polygon_min_angle_deg and polygon_wide_max_angle_deg >= "
                 "polygon_max_angle_deg (got " + std::to_string(p.polygon_wide_min_angle_deg) + " / " +
                 std::to_string(p.polygon_wide_max_angle_deg) + ")";
  });
  t.addRule([&p]() -> std::string {
    return p.edge_offset_px < p.attribution.max_orthogonal_px
               ? ""
               : "edge_offset_px must be < max_orthogonal_distance_px (got " + std::to_string(p.edge_offset_px) + ")";
  });
  t.addRule([&p]() -> std::string { return p.min_attributed_ratio < 1 ? "" : "min_attributed_ratio must be < 1"; });
  return t;
}

dvs_driver::ParamTable nodeParamTable(TrackerNodeSettings& n)
{
  dvs_driver::ParamTable t("dvs_line_tracker");
  t.add("map_file", n.map_file, {}, "line map YAML (empty: the 0.9 m square in the plane z = 0)");
  t.add("calibration_file", n.calibration_file, {},
        "calib.txt (`fx fy cx cy k1 k2 p1 p2 k3`) or camera_info YAML (`.yaml`); empty: wait for `dvs/camera_info`");
  t.add("width", n.width, "px", 1, dvs_calibration::kMaxSensorSide, "sensor width for a calib.txt (a YAML has its own)");
  t.add("height", n.height, "px", 1, dvs_calibration::kMaxSensorSide, "sensor height for a calib.txt");
  t.add("world_frame", n.world_frame, {}, "frame of the map, poses and markers");
  t.add("camera_frame", n.camera_frame, {}, "frame of the estimated camera (TF child)");
  t.add("publish_per_event_poses", n.publish_per_event_poses, "publish `~pose` per pose update (when subscribed)");
  t.add("image_rate", n.image_rate_hz, "Hz", 0, 1000, "`~image` rate limit").min_exclusive = true;
  t.add("marker_rate", n.marker_rate_hz, "Hz", 0, 1000, "`~markers` rate limit").min_exclusive = true;
  t.add("use_imu", n.use_imu, "subscribe to `dvs/imu` (sensor_msgs/Imu) and fuse it (`imu_*` parameters)");
  t.add("body_frame", n.body_frame, {}, "child frame of `~odometry` (empty: camera_frame)");
  t.add("q_body_camera", n.q_body_camera, {}, "R_body_camera as a quaternion 'x y z w' (camera axes -> body axes)");
  t.add("p_body_camera", n.p_body_camera, {}, "the camera's origin in the body frame 'x y z' [m]");
  t.add("output_rate", n.output_rate_hz, "Hz", 0, 10000,
        "`~odometry` at this fixed rate, predicted to the publish time (0: once per event packet)");
  t.add("overload_latency", n.overload_latency_s, "s", 0, 10,
        "queued event packets are worked off within this, tracking every k-th event when the tracker falls behind "
        "(counted in diagnostics; 0: every event, whatever the latency)");
  t.add("max_queued_events", n.max_queued_events, "events", 1000, 1000000000,
        "beyond, the oldest queued packets are dropped (counted in diagnostics)");
  t.addRule([&n]() -> std::string {
    return n.world_frame.empty() || n.camera_frame.empty() ? "world_frame and camera_frame must not be empty" : "";
  });
  t.addRule([&n]() -> std::string {
    Pose T_camera_body;
    return parseBodyCameraExtrinsic(n.q_body_camera, n.p_body_camera, T_camera_body);
  });
  return t;
}

void applySolverName(const std::string& solver_name, LineTrackerParams& params)
{
  if (!parseSolverType(solver_name, params.estimator.solver))
    throw std::invalid_argument("dvs_line_tracker: solver must be 'incremental' or 'full' (got '" + solver_name + "')");
}

std::string validateParams(const LineTrackerParams& params)
{
  LineTrackerParams copy = params;
  std::string solver = solverTypeName(params.estimator.solver);
  return trackerParamTable(copy, solver).validate();
}

bool parseSolverType(const std::string& name, SolverType& type)
{
  if (name == "incremental")
    type = SolverType::kIncremental;
  else if (name == "full")
    type = SolverType::kFullGaussNewton;
  else
    return false;
  return true;
}

const char* solverTypeName(SolverType type)
{
  return type == SolverType::kIncremental ? "incremental" : "full";
}

void loadTrackerParamsYaml(const std::string& path, LineTrackerParams& params)
{
  std::string solver = solverTypeName(params.estimator.solver);
  dvs_driver::ParamTable table = trackerParamTable(params, solver);
  table.loadYaml(path);
  const std::string err = table.validate();
  if (!err.empty())
    throw std::runtime_error(path + ": " + err);
  applySolverName(solver, params);
}
}  // namespace dvs_line_tracker
