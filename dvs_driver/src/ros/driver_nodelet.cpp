// dvs_driver/DriverNodelet: onInit only constructs DriverRos (driver_ros.h), as the node does.
#include "driver_ros.h"

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <memory>

namespace dvs_driver
{
class DriverNodelet : public nodelet::Nodelet
{
private:
  void onInit() override
  {
    try
    {
      driver_.reset(new DriverRos(getNodeHandle(), getPrivateNodeHandle()));
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL_STREAM(e.what());
      throw;
    }
  }
  std::unique_ptr<DriverRos> driver_;
};
}  // namespace dvs_driver

PLUGINLIB_EXPORT_CLASS(dvs_driver::DriverNodelet, nodelet::Nodelet)
