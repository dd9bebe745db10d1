// dvs_driver_node: the driver in its own process; constructs DriverRos as the nodelet does (no
// nodelet manager).
#include "driver_ros.h"

#include <ros/ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "dvs_driver");
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<dvs_driver::DriverRos> driver;
  try
  {
    driver.reset(new dvs_driver::DriverRos(nh, pnh));
  }
  catch (const std::exception& e)
  {
    ROS_FATAL_STREAM(e.what());
    return 1;
  }
  ros::spin();
  driver.reset();
  return 0;
}
