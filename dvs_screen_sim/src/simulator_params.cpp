#include <dvs_screen_sim/simulator_params.h>

namespace dvs_screen_sim
{
dvs_driver::ParamTable simulatorParamTable(SimulatorParams& p)
{
  dvs_driver::ParamTable t("dvs_screen_sim");
  t.add("scenario", p.scenario, scenarioNames(), "the scenario (scene, trajectory, camera)");
  t.add("config_file", p.config_file, {}, "configuration overrides (YAML, keys as for `simulate`)");
  t.add("seed", p.seed, "", 0, 2147483647, "random seed (noise, random trajectory)");
  addSharedRunParams(t, p.run);
  t.add("real_time_factor", p.real_time_factor, "", 0, 1e308, "simulated seconds per wall second (0: as fast as possible)");
  t.add("loop", p.loop, "restart at the end (new time base each run)");
  t.add("wall_clock_stamps", p.wall_clock_stamps,
        "stamps = wall clock at start + simulated time; false: simulated time (+ the configuration's time_offset)");
  t.add("world_frame", p.world_frame, {}, "frame of the ground truth and the map");
  t.add("camera_frame", p.camera_frame, {}, "frame_id of events and camera_info");
  t.add("ground_truth_frame", p.ground_truth_frame, {}, "TF child frame of the ground truth");
  t.add("start_delay", p.start_delay, "s", 0, 1e308, "wait before simulating (consumers connect first)");
  t.add("wait_for_subscribers", p.wait_for_subscribers, "wait for a subscriber on dvs/events before simulating");
  t.addRule([&p]() -> std::string {
    return p.world_frame.empty() || p.camera_frame.empty() || p.ground_truth_frame.empty()
               ? "~world_frame, ~camera_frame, ~ground_truth_frame must not be empty"
               : "";
  });
  return t;
}
}  // namespace dvs_screen_sim
