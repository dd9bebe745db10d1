// simulator_node: runs the software DVS (the same class as dvs_screen_sim/SimulatorNodelet).
#include <dvs_screen_sim/simulator_ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "dvs_screen_sim");
  try
  {
    dvs_screen_sim::SimulatorRos sim(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
  }
  catch (const std::exception& e)
  {
    ROS_FATAL("dvs_screen_sim: %s", e.what());
    return 1;
  }
  return 0;
}
