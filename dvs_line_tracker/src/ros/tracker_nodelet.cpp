// dvs_line_tracker/TrackerNodelet: the same TrackerRos the node runs.
#include <dvs_line_tracker/tracker_ros.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

namespace dvs_line_tracker
{
class TrackerNodelet : public nodelet::Nodelet
{
  void onInit() override
  {
    try
    {
      tracker_ = std::make_unique<TrackerRos>(getNodeHandle(), getPrivateNodeHandle());
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("dvs_line_tracker: %s", e.what());
      throw;
    }
  }
  std::unique_ptr<TrackerRos> tracker_;
};
}  // namespace dvs_line_tracker

PLUGINLIB_EXPORT_CLASS(dvs_line_tracker::TrackerNodelet, nodelet::Nodelet)
