#pragma once
// ROS messages for the simulator's outputs (library dvs_screen_sim_ros).
#include <dvs_calibration/camera_info_conversions.h>
#include <dvs_calibration/camera_model.h>
#include <dvs_screen_sim/wall_pose.h>
#include <dvs_screen_sim/scene.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>

namespace dvs_screen_sim
{
/// Seconds -> ros::Time, exact to the nanosecond (rounded); negative times clamp to zero.
ros::Time secondsToRosTime(double t);

/// Ground truth T_world_camera as PoseStamped in `world_frame`.
geometry_msgs::PoseStamped toPoseStamped(const StampedPose& pose, const std::string& world_frame = "world");
/// Ground truth T_world_camera as a transform world_frame -> child_frame.
geometry_msgs::TransformStamped toTransform(const StampedPose& pose, const std::string& world_frame = "world",
                                            const std::string& child_frame = "dvs_gt");
/// The scene as markers: one LINE_LIST with every map edge (namespace "map_edges") and one
/// TRIANGLE_LIST fan per polygon (namespace "polygons", grey level = reflectance).
visualization_msgs::MarkerArray mapMarkers(const Scene& scene, const ros::Time& stamp,
                                           const std::string& world_frame = "world");
}  // namespace dvs_screen_sim
