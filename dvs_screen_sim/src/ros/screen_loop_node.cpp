// screen_loop: a real DVS filming the screen (thesis ch. 3): the ScreenLoopRos class
// (screen_loop_ros.h) running the ROS-free procedure (screen_loop/screen_loop_procedure.h).
#include <dvs_screen_sim/screen_loop_ros.h>

int main(int argc, char** argv)
{
  ros::init(argc, argv, "screen_loop");
  try
  {
    dvs_screen_sim::ScreenLoopRos node(ros::NodeHandle(), ros::NodeHandle("~"));
    return node.run();
  }
  catch (const std::exception& e)
  {
    ROS_FATAL("screen_loop: %s", e.what());
    return 1;
  }
}
