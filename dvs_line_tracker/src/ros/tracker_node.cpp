// tracker_node: runs TrackerRos (the class the nodelet loads) in its own process.
#include <dvs_line_tracker/tracker_ros.h>

#include <iostream>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "dvs_line_tracker");
  try
  {
    dvs_line_tracker::TrackerRos tracker(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
  }
  catch (const std::exception& e)
  {
    // Also on stderr: the message must reach the user even where rosconsole goes to a log only.
    ROS_FATAL("dvs_line_tracker: %s", e.what());
    std::cerr << "dvs_line_tracker: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
