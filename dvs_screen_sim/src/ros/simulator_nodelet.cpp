// dvs_screen_sim/SimulatorNodelet: the same SimulatorRos the node runs.
#include <dvs_screen_sim/simulator_ros.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

namespace dvs_screen_sim
{
class SimulatorNodelet : public nodelet::Nodelet
{
  void onInit() override
  {
    try
    {
      sim_ = std::make_unique<SimulatorRos>(getNodeHandle(), getPrivateNodeHandle());
    }
    catch (const std::exception& e)
    {
      NODELET_FATAL("dvs_screen_sim: %s", e.what());
      throw;
    }
  }
  std::unique_ptr<SimulatorRos> sim_;
};
}  // namespace dvs_screen_sim

PLUGINLIB_EXPORT_CLASS(dvs_screen_sim::SimulatorNodelet, nodelet::Nodelet)
