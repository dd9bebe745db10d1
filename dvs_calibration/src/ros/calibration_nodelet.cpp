// Nodelet dvs_calibration/CalibrationNodelet: the same CalibrationRos the node runs.
#include <dvs_calibration/calibration_ros.h>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

namespace dvs_calibration
{
class CalibrationNodelet : public nodelet::Nodelet
{
private:
  void onInit() override { impl_ = std::make_unique<CalibrationRos>(getNodeHandle(), getPrivateNodeHandle()); }
  std::unique_ptr<CalibrationRos> impl_;
};
}  // namespace dvs_calibration

PLUGINLIB_EXPORT_CLASS(dvs_calibration::CalibrationNodelet, nodelet::Nodelet)
