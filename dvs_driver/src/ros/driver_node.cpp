// dvs_driver_node: loads dvs_driver/DriverNodelet into this process (same code as the nodelet).
#include <nodelet/loader.h>
#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "dvs_driver");
  nodelet::Loader loader;
  const nodelet::M_string remappings(ros::names::getRemappings());
  const nodelet::V_string args(argv + 1, argv + argc);
  if (!loader.load(ros::this_node::getName(), "dvs_driver/DriverNodelet", remappings, args))
  {
    ROS_FATAL("dvs_driver_node: could not start the driver (see the error above)");
    return 1;
  }
  ros::spin();
  return 0;
}
