#include <dvs_screen_sim/scene.h>
#include <dvs_driver/checked_write.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <fstream>

namespace dvs_screen_sim
{
namespace
{
bool pointInPolygon(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& poly)
{
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
  {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

double frac(double x)
{
  return x - std::floor(x);
}

template <typename T>
T get(const YAML::Node& node, const char* key, const T& fallback, const std::string& where)
{
  if (!node[key])
    return fallback;
  try
  {
    return node[key].as<T>();
  }
  catch (const YAML::Exception& e)
  {
    throw SceneError(where + "." + key + ": wrong type (" + e.what() + ")");
  }
}

/// `modulation: {type: constant|square|sine, frequency_hz, phase, low, high, duty}` of a
/// polygon or an image; keys not given keep their defaults.
void parseModulation(const YAML::Node& mn, const std::string& where, IntensityModulation& m)
{
  const std::string type = get<std::string>(mn, "type", "constant", where + ".modulation");
  if (type == "constant")
    m.type = IntensityModulation::Type::Constant;
  else if (type == "square")
    m.type = IntensityModulation::Type::Square;
  else if (type == "sine")
    m.type = IntensityModulation::Type::Sine;
  else
    throw SceneError(where + ".modulation.type must be constant, square or sine (got '" + type + "')");
  m.frequency_hz = get<double>(mn, "frequency_hz", m.frequency_hz, where + ".modulation");
  m.phase = get<double>(mn, "phase", m.phase, where + ".modulation");
  m.low = get<double>(mn, "low", m.low, where + ".modulation");
  m.high = get<double>(mn, "high", m.high, where + ".modulation");
  m.duty = get<double>(mn, "duty", m.duty, where + ".modulation");
}

/// Square and sine modulations are written out; constant ones need no key, callbacks cannot be.
bool writtenToYaml(const IntensityModulation& m)
{
  return m.type == IntensityModulation::Type::Square || m.type == IntensityModulation::Type::Sine;
}

/// The inverse of parseModulation, for a modulation that is writtenToYaml.
YAML::Node modulationToYaml(const IntensityModulation& m)
{
  YAML::Node mn;
  mn["type"] = m.type == IntensityModulation::Type::Square ? "square" : "sine";
  mn["frequency_hz"] = m.frequency_hz;
  mn["phase"] = m.phase;
  mn["low"] = m.low;
  mn["high"] = m.high;
  mn["duty"] = m.duty;
  return mn;
}

}  // namespace

double IntensityModulation::valueAt(double t, double constant_reflectance) const
{
  switch (type)
  {
    case Type::Constant:
      return constant_reflectance;
    case Type::Square:
    {
      // Snap to the wave's edges (within 1e-7 period) so that a sample taken exactly at a
      // discontinuity sees the new value despite rounding.
      double u = t * frequency_hz - phase;
      const double r = std::round(u);
      if (std::abs(u - r) < 1e-7)
        u = r;
      double f = frac(u);
      if (std::abs(f - duty) < 1e-7)
        f = duty;
      return f < duty ? high : low;
    }
    case Type::Sine:
      return low + (high - low) * 0.5 * (1.0 + std::sin(2 * M_PI * frequency_hz * t + phase));
    case Type::Callback:
      return callback ? callback(t) : constant_reflectance;
  }
  return constant_reflectance;
}

double IntensityModulation::nextDiscontinuity(double t) const
{
  if (type != Type::Square)
    return std::numeric_limits<double>::infinity();
  // Edges at (n + phase) / f (rising) and (n + phase + duty) / f (falling).
  const double u = t * frequency_hz - phase;
  const double n = std::floor(u);
  double best = std::numeric_limits<double>::infinity();
  for (double cand : {n, n + duty, n + 1.0, n + 1.0 + duty, n + 2.0})
  {
    const double tc = (cand + phase) / frequency_hz;
    if (tc > t + 1e-12 && tc < best)
      best = tc;
  }
  return best;
}

void Scene::finalize()
{
  if (!(background_reflectance >= 0 && background_reflectance <= 1))
    throw SceneError("scene.background_reflectance must be in [0, 1]");
  if (!map_up.allFinite() || map_up.norm() < 1e-9)
    throw SceneError("scene.map_up must be a non-zero vector");
  parents_.assign(polygons.size(), -1);
  for (size_t k = 0; k < polygons.size(); ++k)
  {
    const auto& poly = polygons[k];
    const std::string where = "scene polygon " + std::to_string(k) + (poly.name.empty() ? "" : " '" + poly.name + "'");
    if (poly.vertices.size() < 3)
      throw SceneError(where + ": needs at least 3 vertices");
    for (const auto& v : poly.vertices)
      if (!v.allFinite())
        throw SceneError(where + ": non-finite vertex");
    const auto& m = poly.modulation;
    if (!(poly.reflectance >= 0 && poly.reflectance <= 1))
      throw SceneError(where + ": reflectance must be in [0, 1]");
    if (m.type == IntensityModulation::Type::Square || m.type == IntensityModulation::Type::Sine)
    {
      if (!(m.frequency_hz > 0))
        throw SceneError(where + ": modulation.frequency_hz must be > 0");
      if (!(m.low >= 0 && m.low <= 1 && m.high >= 0 && m.high <= 1))
        throw SceneError(where + ": modulation low/high must be in [0, 1]");
      if (!(m.duty > 0 && m.duty < 1))
        throw SceneError(where + ": modulation.duty must be in (0, 1)");
    }
    if (m.type == IntensityModulation::Type::Callback && !m.callback)
      throw SceneError(where + ": callback modulation without a callback");
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const auto& v : poly.vertices)
      centroid += v;
    centroid /= static_cast<double>(poly.vertices.size());
    for (int j = static_cast<int>(k) - 1; j >= 0; --j)
      if (pointInPolygon(centroid, polygons[j].vertices))
      {
        parents_[k] = j;
        break;
      }
  }
  for (size_t k = 0; k < images.size(); ++k)
  {
    auto& im = images[k];
    const std::string where = "scene image " + std::to_string(k) + (im.name.empty() ? "" : " '" + im.name + "'");
    if (im.width <= 0 || im.height <= 0 || im.texels.size() != static_cast<size_t>(im.width) * im.height)
      throw SceneError(where + ": needs width * height texels");
    if (!(im.size.x() > 0) || !(im.size.y() > 0) || !im.top_left.allFinite())
      throw SceneError(where + ": size must be positive and top_left finite");
    if (!(im.update_period >= 0))
      throw SceneError(where + ": update_period must be >= 0");
    if (!(im.response_time >= 0) || (im.update_period > 0 && im.response_time > im.update_period))
      throw SceneError(where + ": response_time must be in [0, update_period]");
    if (im.update_period > 0 && !im.update)
      throw SceneError(where + ": update_period set without an update callback");
    if (!(im.gain_value >= 0))
      throw SceneError(where + ": gain must be >= 0");
    for (float& v : im.texels)
      v = std::clamp(v, 0.0f, 1.0f);
  }
}

void loadImageTexels(const std::string& path, SceneImage& image)
{
  const cv::Mat img = cv::imread(path, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
  if (img.empty())
    throw SceneError("cannot read image file '" + path + "'");
  cv::Mat f;
  img.convertTo(f, CV_32F, img.depth() == CV_16U ? 1.0 / 65535.0 : 1.0 / 255.0);
  image.width = f.cols;
  image.height = f.rows;
  image.texels.resize(static_cast<size_t>(f.cols) * f.rows);
  for (int r = 0; r < f.rows; ++r)
    for (int c = 0; c < f.cols; ++c)
      image.texels[static_cast<size_t>(r) * f.cols + c] = f.at<float>(r, c);
  image.file = path;
}

bool Scene::timeVarying() const
{
  for (const auto& p : polygons)
    if (p.modulation.type != IntensityModulation::Type::Constant)
      return true;
  for (const auto& im : images)
    if (im.gain.type != IntensityModulation::Type::Constant || im.update_period > 0)
      return true;
  return false;
}

double Scene::polygonIntensity(size_t k, double t) const
{
  return polygons[k].modulation.valueAt(t, polygons[k].reflectance);
}

double Scene::underIntensity(size_t k, double t) const
{
  const int parent = k < parents_.size() ? parents_[k] : -1;
  return parent < 0 ? background_reflectance : polygonIntensity(static_cast<size_t>(parent), t);
}

double Scene::nextDiscontinuity(double t) const
{
  double best = std::numeric_limits<double>::infinity();
  for (const auto& p : polygons)
    best = std::min(best, p.modulation.nextDiscontinuity(t));
  for (const auto& im : images)
  {
    best = std::min(best, im.gain.nextDiscontinuity(t));
    if (im.update_period > 0)
    {
      double next = (std::floor(t / im.update_period + 1e-9) + 1.0) * im.update_period;
      if (next <= t + 1e-12)
        next += im.update_period;
      best = std::min(best, next);
    }
  }
  return best;
}

Scene defaultSquareScene(double side, double square_reflectance, double wall_reflectance)
{
  Scene scene;
  scene.background_reflectance = wall_reflectance;
  ScenePolygon sq;
  sq.name = "square";
  sq.reflectance = square_reflectance;
  const double h = side / 2;
  sq.vertices = {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
  scene.polygons.push_back(sq);
  scene.finalize();
  return scene;
}

Scene circleGridScene(int rows, int cols, double spacing, double diameter, double circle_intensity,
                      double board_intensity, int circle_vertices)
{
  if (rows < 1 || cols < 1 || !(spacing > 0) || !(diameter > 0) || circle_vertices < 3)
    throw SceneError("circleGridScene: rows, cols, spacing, diameter, circle_vertices must be positive");
  Scene scene;
  scene.background_reflectance = board_intensity;
  // Vertices on a circle of radius r' such that the polygon has the disc's area.
  const double r = diameter / 2;
  const double rp = r * std::sqrt(2 * M_PI / (circle_vertices * std::sin(2 * M_PI / circle_vertices)));
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
    {
      ScenePolygon c;
      c.name = "circle_" + std::to_string(i) + "_" + std::to_string(j);
      c.reflectance = circle_intensity;
      c.in_map = false;
      const Eigen::Vector2d centre((j - (cols - 1) / 2.0) * spacing, ((rows - 1) / 2.0 - i) * spacing);
      for (int v = 0; v < circle_vertices; ++v)
      {
        const double a = 2 * M_PI * v / circle_vertices;
        c.vertices.push_back(centre + rp * Eigen::Vector2d(std::cos(a), std::sin(a)));
      }
      scene.polygons.push_back(c);
    }
  scene.finalize();
  return scene;
}

Scene sceneFromYaml(const YAML::Node& node)
{
  if (!node || !node.IsMap())
    throw SceneError("scene must be a YAML map");
  Scene scene;
  scene.background_reflectance = get<double>(node, "background_reflectance", 0.9, "scene");
  if (node["map_up"])
  {
    auto up = get<std::vector<double>>(node, "map_up", {}, "scene");
    if (up.size() != 3)
      throw SceneError("scene.map_up must have 3 numbers");
    scene.map_up = Eigen::Vector3d(up[0], up[1], up[2]);
  }
  const YAML::Node polys = node["polygons"];
  if (polys && !polys.IsSequence())
    throw SceneError("scene.polygons must be a list");
  if (polys)
    for (size_t k = 0; k < polys.size(); ++k)
    {
      const YAML::Node pn = polys[k];
      const std::string where = "scene.polygons[" + std::to_string(k) + "]";
      if (!pn.IsMap())
        throw SceneError(where + " must be a map");
      for (const auto& kv : pn)
      {
        const std::string key = kv.first.as<std::string>();
        if (key != "name" && key != "reflectance" && key != "vertices" && key != "modulation" && key != "in_map")
          throw SceneError(where + ": unknown key '" + key + "'");
      }
      ScenePolygon poly;
      poly.name = get<std::string>(pn, "name", "", where);
      poly.reflectance = get<double>(pn, "reflectance", 0.1, where);
      poly.in_map = get<bool>(pn, "in_map", true, where);
      const YAML::Node vn = pn["vertices"];
      if (!vn || !vn.IsSequence())
        throw SceneError(where + ".vertices must be a list of [x, y]");
      for (size_t i = 0; i < vn.size(); ++i)
      {
        std::vector<double> v;
        try
        {
          v = vn[i].as<std::vector<double>>();
        }
        catch (const YAML::Exception&)
        {
        }
        if (v.size() != 2 && !(v.size() == 3 && v[2] == 0.0))
          throw SceneError(where + ".vertices[" + std::to_string(i) + "] must be [x, y] (wall plane z = 0)");
        poly.vertices.emplace_back(v[0], v[1]);
      }
      if (const YAML::Node mn = pn["modulation"])
        parseModulation(mn, where, poly.modulation);
      scene.polygons.push_back(poly);
    }
  const YAML::Node imgs = node["images"];
  if (imgs && !imgs.IsSequence())
    throw SceneError("scene.images must be a list");
  if (imgs)
    for (size_t k = 0; k < imgs.size(); ++k)
    {
      const YAML::Node in = imgs[k];
      const std::string where = "scene.images[" + std::to_string(k) + "]";
      if (!in.IsMap())
        throw SceneError(where + " must be a map");
      for (const auto& kv : in)
      {
        const std::string key = kv.first.as<std::string>();
        if (key != "name" && key != "file" && key != "top_left" && key != "size" && key != "gain" &&
            key != "modulation")
          throw SceneError(where + ": unknown key '" + key + "'");
      }
      SceneImage im;
      im.name = get<std::string>(in, "name", "", where);
      const std::string file = get<std::string>(in, "file", "", where);
      if (file.empty())
        throw SceneError(where + ".file (a grey-level image) is required");
      loadImageTexels(file, im);
      const auto tl = get<std::vector<double>>(in, "top_left", {-0.5, 0.5}, where);
      const auto sz = get<std::vector<double>>(in, "size", {1.0, 1.0}, where);
      if (tl.size() != 2 || sz.size() != 2)
        throw SceneError(where + ": top_left and size must be [x, y]");
      im.top_left = Eigen::Vector2d(tl[0], tl[1]);
      im.size = Eigen::Vector2d(sz[0], sz[1]);
      im.gain_value = get<double>(in, "gain", 1.0, where);
      if (const YAML::Node mn = in["modulation"])
        parseModulation(mn, where, im.gain);
      scene.images.push_back(std::move(im));
    }
  scene.finalize();
  return scene;
}

YAML::Node sceneToYaml(const Scene& scene)
{
  YAML::Node node;
  node["background_reflectance"] = scene.background_reflectance;
  YAML::Node up;
  up.SetStyle(YAML::EmitterStyle::Flow);
  for (int i = 0; i < 3; ++i)
    up.push_back(scene.map_up[i]);
  node["map_up"] = up;
  YAML::Node polys(YAML::NodeType::Sequence);
  for (const auto& p : scene.polygons)
  {
    YAML::Node pn;
    pn["name"] = p.name;
    pn["reflectance"] = p.reflectance;
    pn["in_map"] = p.in_map;
    YAML::Node verts;
    for (const auto& v : p.vertices)
    {
      YAML::Node vv;
      vv.SetStyle(YAML::EmitterStyle::Flow);
      vv.push_back(v.x());
      vv.push_back(v.y());
      verts.push_back(vv);
    }
    pn["vertices"] = verts;
    if (writtenToYaml(p.modulation))
      pn["modulation"] = modulationToYaml(p.modulation);
    polys.push_back(pn);
  }
  node["polygons"] = polys;
  if (!scene.images.empty())
  {
    YAML::Node imgs(YAML::NodeType::Sequence);
    for (const auto& im : scene.images)
    {
      YAML::Node in;
      in["name"] = im.name;
      in["file"] = im.file;
      YAML::Node tl, sz;
      tl.SetStyle(YAML::EmitterStyle::Flow);
      sz.SetStyle(YAML::EmitterStyle::Flow);
      tl.push_back(im.top_left.x());
      tl.push_back(im.top_left.y());
      sz.push_back(im.size.x());
      sz.push_back(im.size.y());
      in["top_left"] = tl;
      in["size"] = sz;
      in["gain"] = im.gain_value;
      if (writtenToYaml(im.gain))
        in["modulation"] = modulationToYaml(im.gain);
      imgs.push_back(in);
    }
    node["images"] = imgs;
  }
  return node;
}

Scene loadSceneYaml(const std::string& path)
{
  YAML::Node node;
  try
  {
    node = YAML::LoadFile(path);
  }
  catch (const YAML::Exception& e)
  {
    throw SceneError("cannot read scene file '" + path + "': " + e.what());
  }
  return sceneFromYaml(node);
}

std::vector<MapSegment> mapSegments(const Scene& scene)
{
  std::vector<MapSegment> segs;
  for (const auto& p : scene.polygons)
  {
    if (!p.in_map)
      continue;
    for (size_t i = 0; i < p.vertices.size(); ++i)
    {
      const auto& a = p.vertices[i];
      const auto& b = p.vertices[(i + 1) % p.vertices.size()];
      segs.push_back({Eigen::Vector3d(a.x(), a.y(), 0.0), Eigen::Vector3d(b.x(), b.y(), 0.0)});
    }
  }
  return segs;
}

void writeLineMapYaml(const std::string& path, const Scene& scene)
{
  dvs_driver::writeFileChecked(path, [&](std::ostream& out) {
    out.precision(9);
    out << "# Line map derived from the simulated scene (world frame: wall plane z = 0, x right, y up).\n";
    out << "frame_id: world\n";
    out << "up: [" << scene.map_up.x() << ", " << scene.map_up.y() << ", " << scene.map_up.z() << "]\n";
    out << "segments:\n";
    for (const auto& s : mapSegments(scene))
      out << "  - [[" << s.a.x() << ", " << s.a.y() << ", " << s.a.z() << "], [" << s.b.x() << ", " << s.b.y()
          << ", " << s.b.z() << "]]\n";
  });
}
}  // namespace dvs_screen_sim
