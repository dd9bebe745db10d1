#pragma once
// The thesis's OpenGL projection pipeline for the screen in the loop (ch. 3.2, Eq. 3.1-3.16).
//
//   X_cam  = M_O X_W                      view matrix (Eq. 3.1/3.2): world -> virtual camera
//   X_clip = K_O X_cam                    projection matrix (Eq. 3.3/3.4), z_clip = 0 (2D scene,
//                                         nothing is depth-clipped), w_clip = z_cam
//   X_vp   = X_clip / w_clip              viewport, [-1, 1]^2, y UP (Eq. 3.6)
//   corrected: X_clip' = Hbar K_O M_O X_W (Eq. 3.15), Hbar = the 3x3 correction H expanded to
//              4x4 (Eq. 3.16): third row and column zero except Hbar(2,2) = 1.
//
// The virtual camera uses the suite's camera frame (x right, y down, z forward), so w_clip =
// z_cam > 0 in front of it; f_Oy is negative (Eq. 3.8) because the viewport's y points up.
// Virtual focal lengths (Eq. 3.7/3.8, generalised from the DVS128's 127 px to any width W and
// height H): f_Ox = f_Dx * 2 / (W - 1), f_Oy = -f_Dy * 2 / (H - 1), so the DVS image border
// maps onto the viewport border; `x_scale` (the thesis's inverse window aspect ratio) further
// multiplies f_Ox when the window is not square and the image must keep square pixels.
//
// All matrices are Eigen column-major, ready for glLoadMatrixd(M.data()).
#include <dvs_calibration/camera_model.h>
#include <dvs_screen_sim/wall_pose.h>

#include <Eigen/Core>

namespace dvs_screen_sim
{
namespace screen_loop
{
/// M_O (Eq. 3.2): [R_cam_world, t_cam_world; 0 0 0 1] for the virtual camera pose T_world_camera.
Eigen::Matrix4d viewMatrix(const Pose& T_world_camera);

/// Virtual focal lengths matched to the DVS (Eq. 3.7/3.8).
struct VirtualFocalLengths
{
  double fx = 1.0;   ///< f_Ox (positive)
  double fy = -1.0;  ///< f_Oy (negative: viewport y is up)
};
/// f_Ox = x_scale * 2 f_Dx / (W - 1), f_Oy = -2 f_Dy / (H - 1). Throws std::invalid_argument
/// for a camera narrower than 2 px or a non-positive x_scale.
VirtualFocalLengths matchedFocalLengths(const dvs_calibration::CameraModel& dvs, double x_scale = 1.0);

/// K_O (Eq. 3.4): rows (f_Ox 0 0 0), (0 f_Oy 0 0), (0 0 0 0), (0 0 1 0).
Eigen::Matrix4d projectionMatrix(const VirtualFocalLengths& f);

/// Hbar (Eq. 3.16): the 3x3 homography expanded to act on homogeneous clip coordinates.
Eigen::Matrix4d expandHomography(const Eigen::Matrix3d& H);

/// Normalise a homography for use on clip coordinates: scaled so that its (2,2) element is
/// +1 when possible (w stays positive for points in front of the camera), else by its norm.
Eigen::Matrix3d normalizeHomography(const Eigen::Matrix3d& H);

/// The full pipeline for one virtual camera: P = Hbar K_O M_O.
class ProjectionPipeline
{
public:
  ProjectionPipeline() = default;
  /// The DVS's intrinsics give the virtual focal lengths; `x_scale` as in matchedFocalLengths.
  explicit ProjectionPipeline(const dvs_calibration::CameraModel& dvs, double x_scale = 1.0);

  void setCorrection(const Eigen::Matrix3d& H) { H_ = normalizeHomography(H); }
  const Eigen::Matrix3d& correction() const { return H_; }
  const VirtualFocalLengths& focalLengths() const { return f_; }

  /// K_O (uncorrected) and Hbar K_O (corrected): what goes into GL_PROJECTION.
  Eigen::Matrix4d projection() const { return projectionMatrix(f_); }
  Eigen::Matrix4d correctedProjection() const { return expandHomography(H_) * projectionMatrix(f_); }

  /// Clip coordinates of a world point seen from T_world_camera (corrected or not).
  Eigen::Vector4d clip(const Pose& T_world_camera, const Eigen::Vector3d& p_world, bool corrected = true) const;
  /// Viewport coordinates (x right, y up, [-1, 1]); false when w_clip <= 0 (behind the camera).
  bool viewport(const Pose& T_world_camera, const Eigen::Vector3d& p_world, Eigen::Vector2d& vp,
                bool corrected = true) const;

  /// The affine map between uncorrected viewport coordinates and the ideal (undistorted) DVS
  /// pixel a DVS at the virtual camera's pose would see (Eq. 3.12 vs 3.6):
  /// x_D = f_Dx x_vp / f_Ox + c_Dx, y_D = f_Dy y_vp / f_Oy + c_Dy.
  Eigen::Matrix3d viewportToIdealDvs() const { return A_; }

private:
  VirtualFocalLengths f_;
  Eigen::Matrix3d H_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d A_ = Eigen::Matrix3d::Identity();
};

/// Viewport (x right, y up, [-1, 1]) -> window pixel coordinates (x right, y DOWN, pixel centres
/// at integers + 0.5 ... i.e. continuous coordinates with (0, 0) the window's top-left corner).
inline Eigen::Vector2d viewportToWindow(const Eigen::Vector2d& vp, int window_width, int window_height)
{
  return {(vp.x() + 1.0) * 0.5 * window_width, (1.0 - vp.y()) * 0.5 * window_height};
}
inline Eigen::Vector2d windowToViewport(const Eigen::Vector2d& win, int window_width, int window_height)
{
  return {win.x() / window_width * 2.0 - 1.0, 1.0 - win.y() / window_height * 2.0};
}

/// Apply a homography to a 2D point (dehomogenised).
inline Eigen::Vector2d applyHomography(const Eigen::Matrix3d& H, const Eigen::Vector2d& p)
{
  const Eigen::Vector3d q = H * p.homogeneous();
  return q.hnormalized();
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
