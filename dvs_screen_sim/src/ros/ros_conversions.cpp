#include <dvs_screen_sim/ros_conversions.h>

#include <cmath>

namespace dvs_screen_sim
{
ros::Time secondsToRosTime(double t)
{
  const int64_t ns = t <= 0 ? 0 : static_cast<int64_t>(std::llround(t * 1e9));
  ros::Time stamp;
  stamp.sec = static_cast<uint32_t>(ns / 1000000000LL);
  stamp.nsec = static_cast<uint32_t>(ns % 1000000000LL);
  return stamp;
}

geometry_msgs::PoseStamped toPoseStamped(const StampedPose& pose, const std::string& world_frame)
{
  geometry_msgs::PoseStamped msg;
  msg.header.stamp = secondsToRosTime(pose.t);
  msg.header.frame_id = world_frame;
  const Eigen::Vector3d p = pose.T_world_camera.p_world_camera();
  const Eigen::Quaterniond q = pose.T_world_camera.q_world_camera();
  msg.pose.position.x = p.x();
  msg.pose.position.y = p.y();
  msg.pose.position.z = p.z();
  msg.pose.orientation.x = q.x();
  msg.pose.orientation.y = q.y();
  msg.pose.orientation.z = q.z();
  msg.pose.orientation.w = q.w();
  return msg;
}

geometry_msgs::TransformStamped toTransform(const StampedPose& pose, const std::string& world_frame,
                                            const std::string& child_frame)
{
  geometry_msgs::TransformStamped msg;
  msg.header.stamp = secondsToRosTime(pose.t);
  msg.header.frame_id = world_frame;
  msg.child_frame_id = child_frame;
  const Eigen::Vector3d p = pose.T_world_camera.p_world_camera();
  const Eigen::Quaterniond q = pose.T_world_camera.q_world_camera();
  msg.transform.translation.x = p.x();
  msg.transform.translation.y = p.y();
  msg.transform.translation.z = p.z();
  msg.transform.rotation.x = q.x();
  msg.transform.rotation.y = q.y();
  msg.transform.rotation.z = q.z();
  msg.transform.rotation.w = q.w();
  return msg;
}

visualization_msgs::MarkerArray mapMarkers(const Scene& scene, const ros::Time& stamp, const std::string& world_frame)
{
  visualization_msgs::MarkerArray array;
  visualization_msgs::Marker lines;
  lines.header.frame_id = world_frame;
  lines.header.stamp = stamp;
  lines.ns = "map_edges";
  lines.id = 0;
  lines.type = visualization_msgs::Marker::LINE_LIST;
  lines.action = visualization_msgs::Marker::ADD;
  lines.pose.orientation.w = 1.0;
  lines.scale.x = 0.01;
  lines.color.r = 0.1f;
  lines.color.g = 0.9f;
  lines.color.b = 0.1f;
  lines.color.a = 1.0f;
  for (const auto& s : mapSegments(scene))
  {
    geometry_msgs::Point a, b;
    a.x = s.a.x();
    a.y = s.a.y();
    a.z = s.a.z();
    b.x = s.b.x();
    b.y = s.b.y();
    b.z = s.b.z();
    lines.points.push_back(a);
    lines.points.push_back(b);
  }
  array.markers.push_back(lines);
  int id = 0;
  for (const auto& poly : scene.polygons)
  {
    visualization_msgs::Marker m;
    m.header = lines.header;
    m.ns = "polygons";
    m.id = id++;
    m.type = visualization_msgs::Marker::TRIANGLE_LIST;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.orientation.w = 1.0;
    m.scale.x = m.scale.y = m.scale.z = 1.0;
    const float g = static_cast<float>(poly.reflectance);
    m.color.r = m.color.g = m.color.b = g;
    m.color.a = 1.0f;
    for (size_t i = 1; i + 1 < poly.vertices.size(); ++i)
      for (size_t j : {size_t(0), i, i + 1})
      {
        geometry_msgs::Point p;
        p.x = poly.vertices[j].x();
        p.y = poly.vertices[j].y();
        p.z = 0.001 * (id);  // slightly in front of the wall, later polygons on top
        m.points.push_back(p);
      }
    array.markers.push_back(m);
  }
  return array;
}
}  // namespace dvs_screen_sim
