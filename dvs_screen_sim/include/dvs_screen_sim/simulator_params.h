#pragma once
// The live simulator's parameters (simulator_node and dvs_screen_sim/SimulatorNodelet): one
// table (the suite's ParamTable: name, field, unit, bounds, documentation) read from ROS
// parameters by SimulatorRos and printed as the README's table. `duration` and `packet_period`
// are the configuration's entries of the same names (sim_config.h). ROS-free.
#include <dvs_driver/param_table.h>
#include <dvs_screen_sim/sim_config.h>

#include <string>

namespace dvs_screen_sim
{
struct SimulatorParams
{
  std::string scenario = "flip";
  std::string config_file;
  int seed = 0;
  SimRunParams run;  ///< duration, packet_period (the others come from the configuration)
  double real_time_factor = 1.0;
  bool loop = false;
  bool wall_clock_stamps = true;
  std::string world_frame = "world";
  std::string camera_frame = "dvs";
  std::string ground_truth_frame = "dvs_gt";
  double start_delay = 0.0;
  bool wait_for_subscribers = false;
};

dvs_driver::ParamTable simulatorParamTable(SimulatorParams& p);
}  // namespace dvs_screen_sim
