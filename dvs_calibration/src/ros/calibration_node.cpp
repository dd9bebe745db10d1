// Node dvs_calibration/calibration_node: runs CalibrationRos (see the README for topics,
// services and parameters).
#include <dvs_calibration/calibration_ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "dvs_calibration");
  try
  {
    dvs_calibration::CalibrationRos node(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
  }
  catch (const std::exception& e)
  {
    ROS_FATAL_STREAM(e.what());
    return 1;
  }
  return 0;
}
