#pragma once
// The suite's one camera model: pinhole + OpenCV "plumb_bob" distortion (k1, k2, p1, p2, k3),
// as in the thesis's Eq. 2.3/2.4 (its k3,k4 = p1,p2; its k5 = k3). Pixel centres at integer
// coordinates, (0,0) top-left; camera frame x right, y down, z forward.
//
// Terms used below:
//   normalized  = (X/Z, Y/Z), undistorted ideal image coordinates
//   distorted normalized = plumb_bob(normalized)
//   pixel       = K * distorted normalized (what the sensor sees)
//   ideal pixel = K * normalized (the undistorted image, same K)
#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <vector>

namespace dvs_calibration
{
/// Thrown for invalid intrinsics or unreadable / malformed calibration files.
class CameraModelError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// The largest sensor side the suite accepts (the biggest event sensors are 1280x960; per-pixel
/// tables of a 4096x4096 sensor take 134 MB): larger sizes are refused before allocating.
constexpr int kMaxSensorSide = 4096;

struct CameraIntrinsics
{
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
};

class CameraModel
{
public:
  /// Default: the DVS128 preset.
  CameraModel();
  /// Validates (positive size and focal lengths, finite values); throws CameraModelError.
  explicit CameraModel(const CameraIntrinsics& intrinsics);

  /// Presets: DVS128 128x128 (the default, 2.8-3.5 mm class lens), DAVIS240 240x180 (Event
  /// Camera Dataset-like), DAVIS346 346x260. `preset(name)` accepts "dvs128", "davis240",
  /// "davis346" (case-insensitive) and throws CameraModelError naming the known ones otherwise.
  static CameraModel dvs128();
  static CameraModel davis240();
  static CameraModel davis346();
  static CameraModel preset(const std::string& name);

  const CameraIntrinsics& intrinsics() const { return k_; }
  int width() const { return k_.width; }
  int height() const { return k_.height; }
  bool hasDistortion() const { return has_distortion_; }

  /// plumb_bob applied to normalized coordinates.
  Eigen::Vector2d distortNormalized(const Eigen::Vector2d& xn) const;
  /// Inverse of distortNormalized (fixed-point iteration, converges to < 1e-10 for the
  /// distortions of real lenses inside the image).
  Eigen::Vector2d undistortNormalized(const Eigen::Vector2d& xd) const;

  Eigen::Vector2d normalizedToPixel(const Eigen::Vector2d& xn) const  // K, no distortion
  {
    return {k_.fx * xn.x() + k_.cx, k_.fy * xn.y() + k_.cy};
  }
  Eigen::Vector2d pixelToNormalized(const Eigen::Vector2d& px) const  // K^-1, no distortion
  {
    return {(px.x() - k_.cx) / k_.fx, (px.y() - k_.cy) / k_.fy};
  }

  /// Project a point in camera coordinates to a (distorted) sensor pixel. Returns false when
  /// the point is not in front of the camera (z <= 1e-9); `px` is then left unchanged.
  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& px) const;
  /// Project without distortion (ideal pixel). Same return convention.
  bool projectIdeal(const Eigen::Vector3d& p_cam, Eigen::Vector2d& px) const;

  /// Sensor pixel (distorted) -> ideal pixel (undistorted, same K).
  Eigen::Vector2d undistortPixel(const Eigen::Vector2d& px) const;
  /// Sensor pixel -> normalized (undistorted) coordinates.
  Eigen::Vector2d pixelToUndistortedNormalized(const Eigen::Vector2d& px) const
  {
    return undistortNormalized(pixelToNormalized(px));
  }
  /// Ideal pixel -> sensor pixel (applies distortion).
  Eigen::Vector2d distortPixel(const Eigen::Vector2d& ideal_px) const
  {
    return normalizedToPixel(distortNormalized(pixelToNormalized(ideal_px)));
  }

  /// Per-pixel lookup table: the ideal (undistorted) pixel coordinates of every sensor pixel,
  /// computed once at construction. `x`, `y` must be inside the sensor (not checked here:
  /// check with inSensor() on untrusted input).
  const Eigen::Vector2f& undistortedPixelLut(int x, int y) const { return lut_[static_cast<size_t>(y) * k_.width + x]; }
  bool inSensor(int x, int y) const { return x >= 0 && y >= 0 && x < k_.width && y < k_.height; }
  bool inImage(const Eigen::Vector2d& px, double margin = 0.0) const
  {
    return px.x() >= -0.5 + margin && px.y() >= -0.5 + margin && px.x() <= k_.width - 0.5 - margin &&
           px.y() <= k_.height - 0.5 - margin;
  }

  /// Camera matrix K as 3x3.
  Eigen::Matrix3d cameraMatrix() const;
  /// (k1, k2, p1, p2, k3)
  Eigen::Matrix<double, 5, 1> distortionCoefficients() const;

private:
  void buildLut();

  CameraIntrinsics k_;
  bool has_distortion_ = false;
  std::vector<Eigen::Vector2f, Eigen::aligned_allocator<Eigen::Vector2f>> lut_;
};

/// Event Camera Dataset calib.txt: one line `fx fy cx cy k1 k2 p1 p2 k3` (the distortion may
/// be omitted: zeros). The file has no image size: pass it.
CameraModel loadCalibTxt(const std::string& path, int width = 128, int height = 128);
void saveCalibTxt(const std::string& path, const CameraModel& camera);

/// ROS camera_info YAML (camera_calibration_parsers layout: image_width, image_height,
/// camera_name, camera_matrix, distortion_model plumb_bob, distortion_coefficients,
/// rectification_matrix, projection_matrix).
CameraModel loadCameraInfoYaml(const std::string& path, std::string* camera_name = nullptr);
void saveCameraInfoYaml(const std::string& path, const CameraModel& camera, const std::string& camera_name);

/// The suite's one rule for camera files: a `.yaml`/`.yml` file is a camera_info YAML (its size
/// is in the file; a given width/height must agree with it), anything else a calib.txt, which
/// has no size: width and height must then be given (> 0). Throws CameraModelError naming the
/// file and the problem.
CameraModel loadCameraFile(const std::string& path, int width = 0, int height = 0,
                           std::string* camera_name = nullptr);
/// True when loadCameraFile reads `path` as camera_info YAML (by its extension).
bool isCameraInfoYamlPath(const std::string& path);
}  // namespace dvs_calibration
