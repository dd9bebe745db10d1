#include <dvs_calibration/camera_model.h>
#include <dvs_driver/checked_write.h>

#include <Eigen/LU>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace dvs_calibration
{
namespace
{
bool finite(double v) { return std::isfinite(v); }
}  // namespace

namespace
{
/// "" when the radial distortion r_d = r (1 + k1 r^2 + k2 r^4 + k3 r^6) increases with r until
/// it reaches the sensor's farthest corner and the corner's undistorted radius is within a
/// factor 3 of its distorted one; else the reason.
std::string checkRadialDistortion(const CameraIntrinsics& k)
{
  double rc = 0;  // distorted normalized radius of the farthest pixel corner
  for (double x : {-0.5, k.width - 0.5})
    for (double y : {-0.5, k.height - 0.5})
      rc = std::max(rc, std::hypot((x - k.cx) / k.fx, (y - k.cy) / k.fy));
  auto rd = [&](double r) {
    const double r2 = r * r;
    return r * (1 + r2 * (k.k1 + r2 * (k.k2 + r2 * k.k3)));
  };
  const int steps = 4000;
  const double r_end = 3.0 * rc, dr = r_end / steps;
  double prev = 0;
  for (int i = 1; i <= steps; ++i)
  {
    const double r = i * dr, v = rd(r);
    if (!(v > prev))
      return "radial distortion k1 " + std::to_string(k.k1) + ", k2 " + std::to_string(k.k2) + ", k3 " +
             std::to_string(k.k3) + " folds back at normalized radius " + std::to_string(r) +
             " before the sensor's corners (" + std::to_string(rc) + "): not a lens the model can undistort";
    if (v >= rc)
    {
      if (r < rc / 3.0)
        return "radial distortion k1 " + std::to_string(k.k1) + ", k2 " + std::to_string(k.k2) + ", k3 " +
               std::to_string(k.k3) + " shrinks the sensor's field of view more than threefold: not a real lens";
      return "";
    }
    prev = v;
  }
  return "radial distortion k1 " + std::to_string(k.k1) + ", k2 " + std::to_string(k.k2) + ", k3 " +
         std::to_string(k.k3) + " widens the sensor's field of view more than threefold: not a real lens";
}
}  // namespace

CameraModel::CameraModel() : CameraModel(dvs128().intrinsics()) {}

CameraModel::CameraModel(const CameraIntrinsics& k) : k_(k)
{
  // The per-pixel undistortion table takes 8 bytes a pixel: bound it before allocating.
  if (k.width <= 0 || k.height <= 0 || k.width > kMaxSensorSide || k.height > kMaxSensorSide)
    throw CameraModelError("camera size must be positive and at most " + std::to_string(kMaxSensorSide) + "x" +
                           std::to_string(kMaxSensorSide) + " (got " + std::to_string(k.width) + "x" +
                           std::to_string(k.height) + "; its undistortion table would take " +
                           std::to_string(std::max<int64_t>(0, int64_t(k.width) * std::max(k.height, 0)) * 8 / 1000000) +
                           " MB)");
  for (double v : {k.fx, k.fy, k.cx, k.cy, k.k1, k.k2, k.p1, k.p2, k.k3})
    if (!finite(v))
      throw CameraModelError("camera intrinsics and distortion must be finite numbers");
  if (k.fx <= 0 || k.fy <= 0)
    throw CameraModelError("focal lengths fx, fy must be positive (got " + std::to_string(k.fx) + ", " +
                           std::to_string(k.fy) + ")");
  // Physical sense: the principal point near the sensor, and a distortion that maps the
  // sensor one-to-one (radially monotonic up to its corners) without shrinking or blowing up its
  // field of view beyond any real lens.
  const double margin_x = 0.25 * k.width, margin_y = 0.25 * k.height;
  if (k.cx < -margin_x || k.cx > k.width + margin_x || k.cy < -margin_y || k.cy > k.height + margin_y)
    throw CameraModelError("principal point (" + std::to_string(k.cx) + ", " + std::to_string(k.cy) +
                           ") is far outside the " + std::to_string(k.width) + "x" + std::to_string(k.height) +
                           " sensor");
  if (std::abs(k.p1) > 0.1 || std::abs(k.p2) > 0.1)
    throw CameraModelError("tangential distortion p1, p2 must be within +-0.1 (got " + std::to_string(k.p1) + ", " +
                           std::to_string(k.p2) + ")");
  const std::string radial = checkRadialDistortion(k);
  if (!radial.empty())
    throw CameraModelError(radial);
  has_distortion_ = k.k1 != 0 || k.k2 != 0 || k.p1 != 0 || k.p2 != 0 || k.k3 != 0;
  buildLut();
}

CameraModel CameraModel::dvs128()
{
  CameraIntrinsics k;
  k.width = 128;
  k.height = 128;
  k.fx = 115.0;
  k.fy = 115.0;
  k.cx = 63.5;
  k.cy = 63.5;
  k.k1 = -0.12;
  k.k2 = 0.03;
  return CameraModel(k);
}

CameraModel CameraModel::davis240()
{
  CameraIntrinsics k;  // close to the Event Camera Dataset's DAVIS240C calibration
  k.width = 240;
  k.height = 180;
  k.fx = 199.092;
  k.fy = 198.828;
  k.cx = 132.192;
  k.cy = 110.712;
  k.k1 = -0.368436;
  k.k2 = 0.150947;
  k.p1 = -0.000296;
  k.p2 = -0.000759;
  return CameraModel(k);
}

CameraModel CameraModel::davis346()
{
  CameraIntrinsics k;
  k.width = 346;
  k.height = 260;
  k.fx = 280.0;
  k.fy = 280.0;
  k.cx = 172.5;
  k.cy = 129.5;
  k.k1 = -0.25;
  k.k2 = 0.08;
  return CameraModel(k);
}

CameraModel CameraModel::preset(const std::string& name)
{
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  if (n == "dvs128")
    return dvs128();
  if (n == "davis240" || n == "davis240c")
    return davis240();
  if (n == "davis346")
    return davis346();
  throw CameraModelError("unknown camera preset '" + name + "' (known: dvs128, davis240, davis346)");
}

Eigen::Vector2d CameraModel::distortNormalized(const Eigen::Vector2d& xn) const
{
  const double x = xn.x(), y = xn.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k_.k1 + r2 * (k_.k2 + r2 * k_.k3));
  const double xy2 = 2.0 * x * y;
  return {x * radial + k_.p1 * xy2 + k_.p2 * (r2 + 2.0 * x * x),
          y * radial + k_.p1 * (r2 + 2.0 * y * y) + k_.p2 * xy2};
}

Eigen::Vector2d CameraModel::undistortNormalized(const Eigen::Vector2d& xd) const
{
  if (!has_distortion_)
    return xd;
  // Newton iteration on distort(x) = xd with the analytic Jacobian, started at xd.
  Eigen::Vector2d x = xd;
  for (int it = 0; it < 30; ++it)
  {
    const double u = x.x(), v = x.y();
    const double r2 = u * u + v * v;
    const double radial = 1.0 + r2 * (k_.k1 + r2 * (k_.k2 + r2 * k_.k3));
    const double dradial_dr2 = k_.k1 + r2 * (2.0 * k_.k2 + 3.0 * r2 * k_.k3);
    const Eigen::Vector2d f = distortNormalized(x) - xd;
    if (f.squaredNorm() < 1e-26)
      break;
    Eigen::Matrix2d J;
    J(0, 0) = radial + 2.0 * u * u * dradial_dr2 + 2.0 * k_.p1 * v + 6.0 * k_.p2 * u;
    J(0, 1) = 2.0 * u * v * dradial_dr2 + 2.0 * k_.p1 * u + 2.0 * k_.p2 * v;
    J(1, 0) = 2.0 * u * v * dradial_dr2 + 2.0 * k_.p1 * u + 2.0 * k_.p2 * v;
    J(1, 1) = radial + 2.0 * v * v * dradial_dr2 + 6.0 * k_.p1 * v + 2.0 * k_.p2 * u;
    const double det = J.determinant();
    if (!(std::abs(det) > 1e-12))
      break;  // outside the invertible region: return the best estimate so far
    x -= J.inverse() * f;
  }
  return x;
}

bool CameraModel::project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& px) const
{
  if (!(p_cam.z() > 1e-9))
    return false;
  px = normalizedToPixel(distortNormalized(Eigen::Vector2d(p_cam.x() / p_cam.z(), p_cam.y() / p_cam.z())));
  return true;
}

bool CameraModel::projectIdeal(const Eigen::Vector3d& p_cam, Eigen::Vector2d& px) const
{
  if (!(p_cam.z() > 1e-9))
    return false;
  px = normalizedToPixel(Eigen::Vector2d(p_cam.x() / p_cam.z(), p_cam.y() / p_cam.z()));
  return true;
}

Eigen::Vector2d CameraModel::undistortPixel(const Eigen::Vector2d& px) const
{
  return normalizedToPixel(undistortNormalized(pixelToNormalized(px)));
}

void CameraModel::buildLut()
{
  lut_.resize(static_cast<size_t>(k_.width) * k_.height);
  for (int y = 0; y < k_.height; ++y)
    for (int x = 0; x < k_.width; ++x)
      lut_[static_cast<size_t>(y) * k_.width + x] = undistortPixel(Eigen::Vector2d(x, y)).cast<float>();
}

Eigen::Matrix3d CameraModel::cameraMatrix() const
{
  Eigen::Matrix3d K;
  K << k_.fx, 0, k_.cx, 0, k_.fy, k_.cy, 0, 0, 1;
  return K;
}

Eigen::Matrix<double, 5, 1> CameraModel::distortionCoefficients() const
{
  Eigen::Matrix<double, 5, 1> d;
  d << k_.k1, k_.k2, k_.p1, k_.p2, k_.k3;
  return d;
}

CameraModel loadCalibTxt(const std::string& path, int width, int height)
{
  std::ifstream in(path);
  if (!in)
    throw CameraModelError(path + ": cannot open calibration file: " + std::strerror(errno));
  std::string line;
  while (std::getline(in, line))
  {
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#')
      continue;
    std::istringstream ss(line);
    std::vector<double> v;
    std::string tok;
    while (ss >> tok)
    {
      char* end = nullptr;
      const double d = std::strtod(tok.c_str(), &end);
      if (end == tok.c_str() || *end != '\0')
        throw CameraModelError(path + ": `" + tok + "` is not a number (expected `fx fy cx cy k1 k2 p1 p2 k3`)");
      v.push_back(d);
    }
    if (v.size() != 4 && v.size() != 8 && v.size() != 9)
      throw CameraModelError(path + ": expected 4, 8 or 9 numbers `fx fy cx cy [k1 k2 p1 p2 [k3]]`, got " +
                             std::to_string(v.size()));
    v.resize(9, 0.0);
    CameraIntrinsics k;
    k.width = width;
    k.height = height;
    k.fx = v[0], k.fy = v[1], k.cx = v[2], k.cy = v[3];
    k.k1 = v[4], k.k2 = v[5], k.p1 = v[6], k.p2 = v[7], k.k3 = v[8];
    try
    {
      return CameraModel(k);
    }
    catch (const CameraModelError& e)
    {
      throw CameraModelError(path + ": " + e.what());
    }
  }
  throw CameraModelError(path + ": no calibration line `fx fy cx cy k1 k2 p1 p2 k3` found");
}

void saveCalibTxt(const std::string& path, const CameraModel& camera)
{
  try
  {
    dvs_driver::writeFileChecked(path, [&](std::ostream& out) {
      const CameraIntrinsics& k = camera.intrinsics();
      out << std::setprecision(17) << k.fx << ' ' << k.fy << ' ' << k.cx << ' ' << k.cy << ' ' << k.k1 << ' '
          << k.k2 << ' ' << k.p1 << ' ' << k.p2 << ' ' << k.k3 << '\n';
    });
  }
  catch (const dvs_driver::WriteError& e)
  {
    throw CameraModelError(std::string("cannot write calibration file ") + e.what());
  }
}

namespace
{
std::vector<double> readMatrix(const YAML::Node& root, const std::string& key, size_t min_size, const std::string& path)
{
  const YAML::Node node = root[key];
  if (!node)
    throw CameraModelError(path + ": missing `" + key + "`");
  const YAML::Node data = node["data"];
  if (!data || !data.IsSequence())
    throw CameraModelError(path + ": `" + key + ".data` must be a list of numbers");
  std::vector<double> v;
  for (const auto& x : data)
    v.push_back(x.as<double>());
  if (v.size() < min_size)
    throw CameraModelError(path + ": `" + key + ".data` needs at least " + std::to_string(min_size) + " numbers");
  return v;
}
}  // namespace

CameraModel loadCameraInfoYaml(const std::string& path, std::string* camera_name)
{
  YAML::Node root;
  try
  {
    root = YAML::LoadFile(path);
  }
  catch (const YAML::BadFile&)
  {
    throw CameraModelError(path + ": cannot open camera_info YAML");
  }
  catch (const YAML::Exception& e)
  {
    throw CameraModelError(path + ": not valid YAML: " + e.what());
  }
  try
  {
    if (!root["image_width"] || !root["image_height"])
      throw CameraModelError(path + ": missing `image_width` / `image_height`");
    CameraIntrinsics k;
    k.width = root["image_width"].as<int>();
    k.height = root["image_height"].as<int>();
    const std::vector<double> K = readMatrix(root, "camera_matrix", 9, path);
    k.fx = K[0], k.cx = K[2], k.fy = K[4], k.cy = K[5];
    if (root["distortion_model"])
    {
      const std::string model = root["distortion_model"].as<std::string>();
      if (model != "plumb_bob" && model != "rational_polynomial")
        throw CameraModelError(path + ": distortion_model `" + model + "` is not supported (use plumb_bob)");
    }
    if (root["distortion_coefficients"])
    {
      std::vector<double> d = readMatrix(root, "distortion_coefficients", 0, path);
      // rational_polynomial's k4-k6 (and anything past plumb_bob's five) cannot be dropped silently.
      for (size_t i = 5; i < d.size(); ++i)
        if (d[i] != 0)
          throw CameraModelError(path + ": distortion coefficient " + std::to_string(i) + " (" + std::to_string(d[i]) +
                                 ") is not zero: only plumb_bob's k1 k2 p1 p2 k3 are supported");
      d.resize(5, 0.0);
      k.k1 = d[0], k.k2 = d[1], k.p1 = d[2], k.p2 = d[3], k.k3 = d[4];
    }
    if (camera_name)
      *camera_name = root["camera_name"] ? root["camera_name"].as<std::string>() : std::string();
    return CameraModel(k);
  }
  catch (const YAML::Exception& e)
  {
    throw CameraModelError(path + ": malformed camera_info YAML: " + e.what());
  }
  catch (const CameraModelError& e)
  {
    const std::string what = e.what();
    throw CameraModelError(what.rfind(path, 0) == 0 ? what : path + ": " + what);
  }
}

void saveCameraInfoYaml(const std::string& path, const CameraModel& camera, const std::string& camera_name)
{
  try
  {
    dvs_driver::writeFileChecked(path, [&](std::ostream& out) {
      const CameraIntrinsics& k = camera.intrinsics();
      out << std::setprecision(12);
      out << "image_width: " << k.width << "\n";
      out << "image_height: " << k.height << "\n";
      out << "camera_name: " << (camera_name.empty() ? "dvs" : camera_name) << "\n";
      out << "camera_matrix:\n  rows: 3\n  cols: 3\n  data: [" << k.fx << ", 0, " << k.cx << ", 0, " << k.fy
          << ", " << k.cy << ", 0, 0, 1]\n";
      out << "distortion_model: plumb_bob\n";
      out << "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [" << k.k1 << ", " << k.k2 << ", " << k.p1
          << ", " << k.p2 << ", " << k.k3 << "]\n";
      out << "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n";
      out << "projection_matrix:\n  rows: 3\n  cols: 4\n  data: [" << k.fx << ", 0, " << k.cx << ", 0, 0, "
          << k.fy << ", " << k.cy << ", 0, 0, 0, 1, 0]\n";
    });
  }
  catch (const dvs_driver::WriteError& e)
  {
    throw CameraModelError(std::string("cannot write camera_info YAML ") + e.what());
  }
}

bool isCameraInfoYamlPath(const std::string& path)
{
  auto ends = [&](const std::string& suffix) {
    return path.size() >= suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  return ends(".yaml") || ends(".yml");
}

CameraModel loadCameraFile(const std::string& path, int width, int height, std::string* camera_name)
{
  if (isCameraInfoYamlPath(path))
  {
    CameraModel camera = loadCameraInfoYaml(path, camera_name);
    if ((width > 0 && width != camera.width()) || (height > 0 && height != camera.height()))
      throw CameraModelError(path + ": the file says " + std::to_string(camera.width()) + "x" +
                             std::to_string(camera.height()) + " pixels but " + std::to_string(width) + "x" +
                             std::to_string(height) + " was given");
    return camera;
  }
  if (width <= 0 || height <= 0)
    throw CameraModelError(path + ": a calib.txt holds no sensor size: give the width and height (e.g. "
                                  "--width 240 --height 180) or use a camera_info YAML");
  return loadCalibTxt(path, width, height);
}
}  // namespace dvs_calibration
