#include <dvs_line_tracker/line_map.h>

#include <yaml-cpp/yaml.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace dvs_line_tracker
{
namespace
{
constexpr double kVertexTolerance = 1e-3;  // metres
constexpr double kMinSegmentLength = 1e-3;

Eigen::Vector3d readVector3(const YAML::Node& node, const std::string& what)
{
  if (!node.IsSequence() || node.size() != 3)
    throw LineMapError(what + " must be a list of 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i)
  {
    try
    {
      v[i] = node[i].as<double>();
    }
    catch (const YAML::Exception&)
    {
      throw LineMapError(what + " must contain numbers");
    }
    if (!std::isfinite(v[i]))
      throw LineMapError(what + " contains a non-finite number");
  }
  return v;
}
}  // namespace

LineMap defaultSquareMap(double side_m)
{
  LineMap map;
  const double h = side_m / 2;
  // Counter-clockwise seen from +z (from the camera side).
  const Eigen::Vector3d c[4] = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  for (int k = 0; k < 4; ++k)
    map.segments.push_back({c[k], c[(k + 1) % 4]});
  finalizeLineMap(map, "default square map");
  return map;
}

void finalizeLineMap(LineMap& map, const std::string& name)
{
  if (map.segments.empty())
    throw LineMapError(name + ": the map has no segments");
  if (!map.up_world.allFinite() || map.up_world.norm() < 1e-9)
    throw LineMapError(name + ": 'up' must be a non-zero vector");
  map.up_world.normalize();
  for (size_t i = 0; i < map.segments.size(); ++i)
  {
    const auto& s = map.segments[i];
    if (!s.p0_world.allFinite() || !s.p1_world.allFinite())
      throw LineMapError(name + ": segment " + std::to_string(i) + " has non-finite coordinates");
    if ((s.p1_world - s.p0_world).norm() < kMinSegmentLength)
      throw LineMapError(name + ": segment " + std::to_string(i) + " is degenerate (shorter than 1 mm)");
  }
  // Closed polygons: walk from each unused segment through shared endpoints.
  map.polygons.clear();
  std::vector<bool> used(map.segments.size(), false);
  auto close = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).norm() < kVertexTolerance; };
  for (size_t start = 0; start < map.segments.size(); ++start)
  {
    if (used[start])
      continue;
    MapPolygon poly;
    std::vector<bool> in_chain(map.segments.size(), false);
    poly.segment_ids.push_back(static_cast<int>(start));
    poly.corners_world.push_back(map.segments[start].p0_world);
    in_chain[start] = true;
    Eigen::Vector3d end = map.segments[start].p1_world;
    bool closed = false;
    while (true)
    {
      if (close(end, map.segments[start].p0_world) && poly.segment_ids.size() >= 3)
      {
        closed = true;
        break;
      }
      int next = -1;
      bool flip = false;
      for (size_t j = 0; j < map.segments.size() && next < 0; ++j)
      {
        if (in_chain[j] || used[j])
          continue;
        if (close(map.segments[j].p0_world, end))
          next = static_cast<int>(j);
        else if (close(map.segments[j].p1_world, end))
        {
          next = static_cast<int>(j);
          flip = true;
        }
      }
      if (next < 0)
        break;
      in_chain[next] = true;
      poly.segment_ids.push_back(next);
      poly.corners_world.push_back(end);
      end = flip ? map.segments[next].p0_world : map.segments[next].p1_world;
    }
    if (!closed)
      continue;
    for (int id : poly.segment_ids)
      used[id] = true;
    // Planarity.
    const Eigen::Vector3d centroid = cornerCentroid(poly);
    Eigen::MatrixXd a(poly.corners_world.size(), 3);
    for (size_t k = 0; k < poly.corners_world.size(); ++k)
      a.row(k) = (poly.corners_world[k] - centroid).transpose();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinV);
    const Eigen::Vector3d normal = svd.matrixV().col(2);
    poly.planar = true;
    double worst = 0;
    for (const auto& c : poly.corners_world)
      worst = std::max(worst, std::abs(normal.dot(c - centroid)));
    // The initialisation solves a planar PnP on a polygon's corners and the tracker's attribution
    // assumes flat faces: a warped polygon (a typo in a coordinate) would be "tracked" metres off.
    if (worst > 1e-3)
    {
      std::ostringstream msg;
      msg << name << ": the closed polygon of segments";
      for (int id : poly.segment_ids)
        msg << " " << id;
      msg << " is not planar (a corner lies " << worst * 1e3
          << " mm off the polygon's best-fit plane; corners must be within 1 mm)";
      throw LineMapError(msg.str());
    }
    map.polygons.push_back(poly);
  }
  if (map.polygons.empty())
    throw LineMapError(name + ": the segments form no closed polygon (initialisation needs at least one; "
                              "endpoints must coincide within 1 mm)");
}

LineMap parseLineMap(const std::string& yaml_text, const std::string& name)
{
  YAML::Node root;
  try
  {
    root = YAML::Load(yaml_text);
  }
  catch (const YAML::Exception& e)
  {
    throw LineMapError(name + ": not valid YAML: " + e.what());
  }
  if (!root.IsMap())
    throw LineMapError(name + ": expected a YAML mapping with 'segments'");
  LineMap map;
  if (root["frame_id"])
    map.frame_id = root["frame_id"].as<std::string>();
  try
  {
    if (root["up"])
      map.up_world = readVector3(root["up"], "'up'");
    const YAML::Node segs = root["segments"];
    if (!segs || !segs.IsSequence() || segs.size() == 0)
      throw LineMapError("'segments' is missing or empty");
    for (size_t i = 0; i < segs.size(); ++i)
    {
      const std::string what = "segment " + std::to_string(i);
      if (!segs[i].IsSequence() || segs[i].size() != 2)
        throw LineMapError(what + " must be a pair of 3D points [[x,y,z],[x,y,z]]");
      map.segments.push_back({readVector3(segs[i][0], what + " start"), readVector3(segs[i][1], what + " end")});
    }
  }
  catch (const LineMapError& e)
  {
    throw LineMapError(name + ": " + e.what());
  }
  finalizeLineMap(map, name);
  return map;
}

LineMap loadLineMap(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw LineMapError("cannot open map file '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseLineMap(ss.str(), path);
}

std::string lineMapToYaml(const LineMap& map)
{
  std::ostringstream out;
  out.precision(9);
  auto v = [&](const Eigen::Vector3d& p) { out << "[" << p.x() << ", " << p.y() << ", " << p.z() << "]"; };
  out << "frame_id: " << map.frame_id << "\nup: ";
  v(map.up_world);
  out << "\nsegments:\n";
  for (const auto& s : map.segments)
  {
    out << "  - [";
    v(s.p0_world);
    out << ", ";
    v(s.p1_world);
    out << "]\n";
  }
  return out.str();
}

Eigen::Vector3d frontNormal(const MapPolygon& poly)
{
  const auto& corners = poly.corners_world;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < corners.size(); ++i)
    normal += corners[i].cross(corners[(i + 1) % corners.size()]);
  return normal;
}

Eigen::Vector3d cornerCentroid(const MapPolygon& poly)
{
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& c : poly.corners_world)
    centroid += c;
  return centroid / static_cast<double>(poly.corners_world.size());
}

std::vector<Eigen::Isometry3d> lineMapSymmetries(const LineMap& map, double tolerance_m)
{
  std::vector<Eigen::Isometry3d> out;
  if (map.segments.empty() || map.polygons.empty())
    return out;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& s : map.segments)
    centroid += s.p0_world + s.p1_world;
  centroid /= 2.0 * static_cast<double>(map.segments.size());
  // The plane's normal (the first polygon's), and every endpoint on it.
  Eigen::Vector3d normal = frontNormal(map.polygons.front());
  if (normal.norm() < 1e-12)
    return out;
  normal.normalize();
  for (const auto& s : map.segments)
    if (std::abs(normal.dot(s.p0_world - centroid)) > tolerance_m || std::abs(normal.dot(s.p1_world - centroid)) > tolerance_m)
      return out;
  auto near = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).norm() <= tolerance_m; };
  auto mapsOntoMap = [&](const Eigen::Isometry3d& S) {
    for (const auto& s : map.segments)
    {
      const Eigen::Vector3d a = S * s.p0_world, b = S * s.p1_world;
      if (std::none_of(map.segments.begin(), map.segments.end(), [&](const MapSegment& t) {
            return (near(a, t.p0_world) && near(b, t.p1_world)) || (near(a, t.p1_world) && near(b, t.p0_world));
          }))
        return false;
    }
    return true;
  };
  // Candidate angles: the first segment turned onto each segment (either direction).
  const Eigen::Vector3d d0 = map.segments.front().p1_world - map.segments.front().p0_world;
  for (const auto& t : map.segments)
    for (int reversed = 0; reversed < 2; ++reversed)
    {
      const Eigen::Vector3d d = reversed ? Eigen::Vector3d(t.p0_world - t.p1_world) : Eigen::Vector3d(t.p1_world - t.p0_world);
      const double angle = std::atan2(normal.dot(d0.cross(d)), d0.dot(d));
      if (std::abs(angle) < 1e-6)
        continue;
      const Eigen::Isometry3d S = Eigen::Translation3d(centroid) * Eigen::AngleAxisd(angle, normal) * Eigen::Translation3d(-centroid);
      if (mapsOntoMap(S) && std::none_of(out.begin(), out.end(), [&](const Eigen::Isometry3d& q) { return q.isApprox(S, 1e-6); }))
        out.push_back(S);
    }
  return out;
}
}  // namespace dvs_line_tracker
