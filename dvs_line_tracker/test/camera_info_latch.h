#pragma once
// For the tracker rostests: the camera info published latched on /dvs/camera_info. The tracker
// unsubscribes from camera_info once it has one (tracker_ros.cpp): that disconnect says the
// camera info was delivered.
#include <dvs_calibration/camera_info_conversions.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>

#include <atomic>

class CameraInfoLatch
{
public:
  CameraInfoLatch(ros::NodeHandle& nh, const dvs_calibration::CameraModel& camera)
  {
    pub_ = nh.advertise<sensor_msgs::CameraInfo>(
        "/dvs/camera_info", 1, ros::SubscriberStatusCallback(),
        [this](const ros::SingleSubscriberPublisher&) { ++disconnects_; }, ros::VoidConstPtr(), true);
    pub_.publish(dvs_calibration::toCameraInfoMsg(camera, "dvs"));
  }
  /// The tracker took it (and unsubscribed).
  bool taken() const { return disconnects_.load() > 0; }

private:
  std::atomic<int> disconnects_{0};
  ros::Publisher pub_;
};
