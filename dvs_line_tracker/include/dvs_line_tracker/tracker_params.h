#pragma once
// The tracker's parameters: the struct the parts read, and the one table (name, field, unit,
// bounds, meaning) that the offline tool's YAML file, the nodelet's ROS parameters, validation
// and the README's parameter table all come from (dvs_driver/param_table.h).
#include <dvs_driver/param_table.h>
#include <dvs_line_tracker/hough_line_detector.h>
#include <dvs_line_tracker/imu_fusion_params.h>
#include <dvs_line_tracker/polygon_search.h>
#include <dvs_line_tracker/pose_estimator.h>
#include <dvs_line_tracker/pose_initializer.h>
#include <dvs_line_tracker/segment_attribution.h>

#include <string>

namespace dvs_line_tracker
{
struct LineTrackerParams
{
  HoughParams hough;
  PolygonSearchParams polygon;
  /// When no polygon within polygon.min/max_turn_angle_deg starts tracking in a detection
  /// attempt, the polygons with a turn between these wider bounds and the usual ones are tried
  /// (a square tilted by 60 deg, close to a wide lens, turns by 30-35 deg at its far corners).
  /// Equal to the usual bounds: off.
  double polygon_wide_min_angle_deg = 25.0;
  double polygon_wide_max_angle_deg = 155.0;
  PoseInitParams init;
  /// Events within 2 px of a projected segment (thesis) and, unlike the thesis's 10 px, at most
  /// 2 px beyond its ends: events beyond a side's end come from the neighbouring side's corner,
  /// which biased the sides that fire little along the weakly observable lateral / pitch pair
  /// (twenty-ninth session: accuracy classes' RMS x0.944, the start sweep's false
  /// initialisations 1 -> 0).
  AttributionParams attribution{2.0, 2.0};
  PoseEstimatorParams estimator;
  ImuFusionParams imu;  ///< used when an IMU stream is given (imu_propagator.h)
  /// Edge position inside the firing pixel (edge_run_model.h): each attributed event is moved
  /// from its pixel centre to where the pixel's log level, integrated from its events, puts the
  /// edge, towards the segment's bright side (learned online from event polarities and the
  /// edge's normal motion). Off: the constant `edge_offset_px` (the mean of that offset; events
  /// of an edge lie on its dark side on average).
  bool edge_run_model = true;
  double contrast_threshold = 0;    ///< the sensor's contrast threshold C (log intensity); 0: learned from the run lengths
  double contrast_threshold_prior = 0.3; ///< C used until it is learned (0: the constant edge_offset_px until then)
  int contrast_learning_runs = 1000; ///< completed runs (of >= 3 events) before the learned C replaces the prior
  double edge_contrast_ratio = 9.0; ///< bright / dark intensity across the tracked edges (black print on white paper: ~9)
  double edge_offset_px = 0.15;     ///< constant offset (no run model, or until C is learned); 0: pixel centres
  /// Buffered events are dropped once their projected segment has moved this far (along its
  /// normal, at the event) since they were inserted: buffers then span a bounded image motion,
  /// long when the edge is slow, short when fast. 0: off (thesis: count only).
  double buffer_motion_px = 0.5;
  /// Damping while part of the map is outside the image (fewer, shorter lines constrain the
  /// pose); `estimator.damping` otherwise. Updated at every quality check.
  double damping_partial_view = 1.0;
  /// Below this many attributed events per second the partial-view damping falls in proportion
  /// to the rate, down to `estimator.damping`: a per-event prior that holds the pose for a time,
  /// not for a number of events (a slow camera's pose otherwise trails its motion). 0: off.
  double damping_partial_view_rate = 30000;
  int buffer_size = 35;              ///< events per segment buffer (thesis: 8; 35 measured most accurate with the motion bound and the later initialiser, BENCHMARKS.md 2026-11-26)
  /// The pose is solved once per this many attributed events; the events in between are
  /// attributed and buffered against the last solved pose, which they report. 1: every event
  /// (the thesis). Larger: faster (BENCHMARKS.md: 4 gives 1.4-1.8x), accuracy per sequence.
  int solve_every_events = 1;
  /// ... and once the attributed events since the last solve lie, summed, at least this far from
  /// their projected segments [px]: an event on its line carries little news for the pose, and
  /// its solve waits for the next event off its line; that solve then takes the damped steps of
  /// the events held back as well (on the same normal equations: without them the estimate lags
  /// in the weakly observed directions). 1.2x faster on the DVS128 flip at the same accuracy
  /// (BENCHMARKS.md, thirtieth session). 0: every event (the thesis).
  double solve_min_offset_px = 0.5;
  /// ... and at most this many times per second of event time [Hz], spread evenly, with bursts
  /// of up to 1 ms worth of solves let through (an edge crossing a pixel row fires dozens of
  /// events at once). Below this event rate every attributed event is solved; above it the
  /// events between solves are attributed and buffered against the last solved pose and the
  /// next solve uses them all: at high event rates the pose moves little from event to event,
  /// and the tracker keeps up with fast sensors. 0: no limit.
  double max_solve_rate = 200000;
  /// The damped information matrix (sum of the segments' H) is assembled and factored at most
  /// this many solves apart; the solves between reuse its factor with the current gradient. One
  /// event changes one segment's buffer by one event: the information changes little from solve
  /// to solve, the gradient carries the news (BENCHMARKS.md, 2026-11-26). 1: every solve.
  int factor_every_solves = 8;
  /// ... and sooner: once an element of the information's diagonal has changed by this fraction
  /// of its factored value (the absolute changes of the re-linearised segments summed; a factor
  /// that under-states the information overshoots: with thesis-size buffers of 8 events and
  /// almost no damping, a fixed 8 solves lost the 2000 deg/s flip), a segment turned active or
  /// inactive, or a quality check (damping, visibility) ran. 0: every solve.
  double factor_information_change = 0.05;
  /// The initialisation's event counts and pixel gaps (Hough window and threshold, segment gap,
  /// detection interval, refinement events) are given for a 128x128 sensor and scaled by
  /// sqrt(width * height) / 128 on larger sensors (their edges are longer and fire more events);
  /// the neighbour filter's horizon by width * height / 128^2 (the same events per pixel).
  bool init_scale_with_sensor = true;
  /// Validation (side coverage) uses this many Hough windows of the latest voted events: slow
  /// edges draw themselves over a longer time than a window holds.
  double init_evidence_windows = 4.0;
  /// After a loss the last tracked pose is tried first (refined on the recent events, validated
  /// like a detection) for this long [s]: re-acquisition without a whole polygon in view. 0: off.
  double reacquire_prior_s = 2.0;
  /// The prior's capture range [px]: it is refined on the window events within this distance of
  /// its projected map first, then within half of it, ... down to hough_attribution_distance_px
  /// (the camera moved while the track was lost). 0: only at the Hough's distance.
  double reacquire_capture_px = 4.0;
  /// While tracking, an event gap longer than this [s] (a blackout: a real sensor's background
  /// activity alone fires every few ms) makes the pose stale: the track is declared lost and
  /// re-acquired (the last pose tried first); with a healthy IMU (imu_propagator.h) the IMU
  /// carries the pose across it instead (up to imu_max_bridge). 0: off.
  double max_event_gap_s = 0.1;
  /// When the progressive Hough's segments (hough_remove_found_votes) give no pose to start
  /// from or to confirm, the same attempt looks again with the full Hough (every candidate line
  /// split into segments): the progressive Hough is fast and finds the sides a thick edge's
  /// neighbouring lines hide, the full one finds sides that noise events took.
  bool init_full_hough_fallback = true;
  int init_check_interval = 200;     ///< voted events between detection attempts while initialising
  double init_min_check_period_s = 0.005;  ///< and at least this much event time between attempts (bounds the CPU at high rates)
  int init_min_events = 100;         ///< voted events before the first detection attempt
  int init_refine_events = 400;      ///< latest window events used to refine the initial pose (point-to-line)
  /// When tracking starts, the events since the oldest one the initial pose was refined on (all
  /// of them, not only the voted ones) go through the per-event update at once: that pose fits
  /// events spread over time, i.e. lags a fast motion by half their span; the update catches it
  /// up to the latest event before the first pose is given.
  bool init_catch_up = true;
  double init_border_margin_px = 3.0; ///< detected segments this close to an image border along it are ignored
  double init_min_coverage = 0.6;   ///< each projected side's visible length must be this much covered by window events
  int init_confirmations = 1;          ///< a detection is accepted when this many of the last 4 detections agree with it
  double init_confirm_position_ratio = 0.1;   ///< agreement: position difference / distance
  double init_confirm_angle_deg = 8.0;        ///< agreement: orientation difference
  /// A symmetric polygon's pose must be this much more upright (cosine between projected map up
  /// and image up) than its other rotations that fit the corners: 0.2 waits while the roll is
  /// within about 8 deg of the +-45 deg where the square's two rotations are equally upright.
  double init_min_up_margin = 0.2;
  /// ... and only while the camera rolls slower than this (the roll rate between the confirming
  /// detections): mid-flip, the camera need not be near upright.
  double init_max_roll_rate_deg_s = 500.0;
  double init_max_inside_ratio = 0.3; ///< window events well inside the polygon / events on its sides, upper bound
  double init_max_surrounding_coverage = 0.4; ///< covered fraction of the strips 3 attribution distances beside each side (its quieter side), upper bound (1: no limit)
  /// Fraction of the Hough window's events an initial pose must explain (within the attribution
  /// distance of a projected map side); open polygons and maps of several polygons need 0.5.
  double init_min_explained = 0.25;
  /// An initial pose may see its polygon at most this far off the polygon's normal (tracking goes
  /// on beyond it; 90: no limit).
  double init_max_view_angle_deg = 70.0;
  // Tracking-quality monitoring.
  int quality_check_interval = 512;  ///< events between quality checks while tracking
  int min_visible_segments = 3;      ///< fewer visible (>= min_visible_length_px inside the image) -> lost
  double min_visible_length_px = 12.0;
  /// Fewer than min_visible_segments visible, but two meeting at a corner, for up to this long (event
  /// time): the track is held (the estimate goes on, no pose is reported) and resumes when a third
  /// side comes back (a corner of the map briefly alone in view, as in a fast flip); lost after
  /// it, from the pose before the partial view. 0: lost at once.
  double partial_view_grace_s = 0.05;
  double max_mean_residual_px = 1.5; ///< mean |point-to-line| distance over the buffers above this -> lost
  double min_attributed_ratio = 0.02;///< attributed / all events in a check interval below this -> lost
  /// ... and no more than 1.5x chance, and at least this share of the events not attributed
  /// are structure: next to two others of them (neighbour_activity.h; pure noise gives ~2.2 %,
  /// the edges of a scene the pose does not explain 40-90 %).
  double min_unattributed_structure = 0.1;
  /// The horizon of that neighbour test, in events for a 128x128 sensor (scaled by pixels as the
  /// initialisation's filter horizon; its own so that widening the Hough filter's horizon for
  /// slow, noisy scenes does not make the loss test call noise structure).
  int loss_neighbour_events = 500;
  /// A check attributing less than this fraction of the track's own level (a running mean, at
  /// least 50 %) is a loss when at least half of the rest is structure and the buffers' mean
  /// residual is >= 0.4 px (a slip after an occlusion; 0: off).
  double attribution_drop_ratio = 0.35;
  /// A visible side that moved at least 1 px across the image (net, over the last 8 snapshots
  /// of the projections, >= 10 ms apart) with fewer than this fraction of the events its
  /// polygon's densest side fired per swept px^2, while events no side explains arrive near the
  /// polygon (its edge fires elsewhere), judged so for 0.1 s, is a loss: no edge is where the
  /// pose puts it (silent_side_check.h; 0: off).
  double loss_silent_side_ratio = 0.1;
  double min_depth_m = 0.05;         ///< the near plane: segments crossing it are clipped there; wholly closer -> lost
  /// Event time going back by more than this (a bag replayed into a running tracker) restarts
  /// the tracker (everything time-dependent is forgotten) and says so.
  double max_time_backwards_s = 0.1;
};

/// The table of every tracker parameter bound to the fields of `params` (names as in YAML files,
/// ROS parameters and the README), with units, bounds, cross-parameter rules and meanings. The
/// solver is the string parameter `solver` bound to `solver_name` ("incremental" or "full"):
/// call applySolverName after reading.
dvs_driver::ParamTable trackerParamTable(LineTrackerParams& params, std::string& solver_name);
/// Copy the solver named by the table's `solver` parameter into `params`.
void applySolverName(const std::string& solver_name, LineTrackerParams& params);

/// The ROS node's own settings (beside the tracker's parameters): files, frames, outputs.
struct TrackerNodeSettings
{
  std::string map_file;          ///< line map YAML ("" = the 0.9 m square)
  std::string calibration_file;  ///< calib.txt or camera_info YAML ("" = wait for dvs/camera_info)
  int width = 128, height = 128; ///< sensor size for a calib.txt
  std::string world_frame = "world", camera_frame = "dvs";
  bool publish_per_event_poses = true;
  double image_rate_hz = 30.0, marker_rate_hz = 10.0;
  bool use_imu = true;             ///< subscribe to dvs/imu and fuse it (imu_* parameters)
  std::string body_frame;          ///< child frame of ~odometry ("" = camera_frame)
  std::string q_body_camera = "0 0 0 1";  ///< R_body_camera "x y z w" (camera axes -> body axes)
  std::string p_body_camera = "0 0 0";    ///< the camera's origin in the body frame "x y z" [m]
  double output_rate_hz = 0.0;     ///< ~odometry at this fixed rate, predicted to the publish time (0: once per event packet)
  /// Overload (OverloadGovernor): queued packets are worked off within this, tracking every
  /// k-th event when needed (0: every event, whatever the latency).
  double overload_latency_s = 0.1;
  int max_queued_events = 4000000;  ///< beyond, the oldest queued packets are dropped (counted)
};
/// The node's settings as a table (the ROS node reads this merged with trackerParamTable).
dvs_driver::ParamTable nodeParamTable(TrackerNodeSettings& settings);

/// Validate parameters; returns an empty string when fine, else a message naming the parameter.
std::string validateParams(const LineTrackerParams& params);

/// "incremental" or "full" (anything else: false).
bool parseSolverType(const std::string& name, SolverType& type);
const char* solverTypeName(SolverType type);

/// Read parameters from a flat YAML mapping (names as in the table). Throws std::runtime_error
/// naming the file and the key on unknown keys or wrong types, and the validation message on
/// invalid values.
void loadTrackerParamsYaml(const std::string& path, LineTrackerParams& params);
}  // namespace dvs_line_tracker
