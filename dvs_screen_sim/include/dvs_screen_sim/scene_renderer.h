#pragma once
// Area-correct rendering of a planar Scene seen by a (distorted) camera, pixel by pixel.
//
// Each sensor pixel is a unit square in the sensor image; its footprint in the undistorted
// normalized image plane is the quadrilateral of its 4 undistorted corners (a lookup table
// computed once). The scene's polygons, clipped to the camera's front (z > z_near) and
// projected into that plane (straight edges stay straight there), are clipped against the
// footprint (Sutherland-Hodgman); the pixel's intensity is the area-weighted mix
// background + sum_k coverage_k * (I_k - I_under_k). No supersampling, no staircase.
//
// Only pixels near a projected edge can change while the camera moves a fraction of a pixel:
// appendEdgePixels() lists them (a band of ~0.85 px around every projected edge, in sensor
// pixels, so lens distortion is accounted for) without scanning the image.
//
// Emissive images (SceneImage) are integrated over the footprint by supersampling in texture
// space (the footprint's corners are intersected with the wall).
//
// Not thread-safe (scratch buffers); one renderer per thread.
#include <dvs_calibration/camera_model.h>
#include <dvs_screen_sim/wall_pose.h>
#include <dvs_screen_sim/scene.h>

#include <cstdint>
#include <limits>
#include <vector>

namespace dvs_screen_sim
{
class SceneRenderer
{
public:
  /// The scene must be finalized (Scene::finalize); both are copied.
  SceneRenderer(const dvs_calibration::CameraModel& camera, const Scene& scene);

  /// Set the camera pose and the time (for modulated intensities); projects the scene.
  void setState(const Pose& T_world_camera, double t);

  /// Area-correct linear intensity of sensor pixel (x, y) for the current state.
  double pixelIntensity(int x, int y) const;
  /// The whole image (row-major, width * height) for the current state.
  void renderImage(std::vector<double>& image) const;

  /// Append the indices (y * width + x) of pixels whose footprint an edge of the current state
  /// touches (within `band_radius` px of the edge). `marks` (width * height entries) and `mark`
  /// deduplicate: a pixel with marks[i] == mark is skipped, listed pixels get marks[i] = mark.
  void appendEdgePixels(std::vector<int32_t>& pixels, std::vector<uint32_t>& marks, uint32_t mark) const;

  /// The largest image displacement [sensor px] that the edge points visible now (spaced <= 3 px
  /// along every edge inside the image) undergo when the camera moves to T_world_camera_other.
  /// Points that leave the camera's front count as +inf... capped at 1e6.
  double maxImageMotion(const Pose& T_world_camera_other) const;

  /// True when the scene has images: their content moves everywhere, not only at edges, so
  /// every pixel must be re-evaluated at every sample.
  bool hasImages() const { return !scene_.images.empty(); }
  /// True when the images' contribution to some pixel may differ from the previous setState()
  /// (the camera moved, an image's gain changed or its content was refreshed). A still camera
  /// filming a monitor then re-evaluates every pixel only at the refreshes.
  bool imagesChanged() const { return hasImages() && images_changed_; }
  /// The longest response_time of the images whose content was updated by the last setState()
  /// (0 if none): the change fades in over that time.
  double contentTransition() const { return content_transition_; }
  const dvs_calibration::CameraModel& camera() const { return camera_; }
  const Scene& scene() const { return scene_; }
  int width() const { return width_; }
  int height() const { return height_; }

  double band_radius = 0.85;  ///< [px]

private:
  struct ProjectedPolygon
  {
    std::vector<Eigen::Vector2d> v;  ///< normalized image plane, after near clipping
    Eigen::Vector2d lo, hi;          ///< bounding box
    double delta = 0;                ///< intensity minus the intensity under it
    double orientation = 1.0;        ///< sign of the projected polygon's signed area
    bool convex = false;             ///< convex (and small enough for the fast clipper)
    bool valid = false;
  };

  struct ProjectedImage
  {
    std::vector<Eigen::Vector2d> v;  ///< outline in the normalized image plane, after near clipping
    Eigen::Vector2d lo, hi;
    double gain = 1.0;
    int64_t frame = std::numeric_limits<int64_t>::min();
    bool valid = false;
  };

  double clippedArea(const Eigen::Vector2d* quad, double orientation, const std::vector<Eigen::Vector2d>& poly) const;
  /// Area of the (convex) footprint quad inside a convex polygon: clips the quad by the
  /// polygon's edges, skipping edges that do not cut it (most of them) and stopping at 0.
  static double convexClippedArea(const Eigen::Vector2d* quad, const ProjectedPolygon& pp);
  void projectWallPolygon(const std::vector<Eigen::Vector2d>& wall, const Eigen::Matrix3d& R_cam_world,
                          const Eigen::Vector3d& t_cam_world, std::vector<Eigen::Vector2d>& out) const;
  void addVisibleEdgePoints(const std::vector<Eigen::Vector2d>& outline);
  double imageIntensity(size_t k, int x, int y, double under) const;
  Eigen::Vector2d cornerNormalized(int cx, int cy) const { return corners_[static_cast<size_t>(cy) * (width_ + 1) + cx]; }
  Eigen::Vector2d toSensorPixel(const Eigen::Vector2d& xn) const;

  dvs_calibration::CameraModel camera_;
  Scene scene_;
  int width_, height_;
  std::vector<Eigen::Vector2d> corners_;  ///< (W+1) x (H+1) undistorted normalized pixel corners
  Eigen::Vector2d view_lo_, view_hi_;     ///< normalized bounds of the sensor (+ margin)
  double px_per_normalized_;              ///< ~fx, for subdivision lengths
  Pose T_world_camera_;
  Eigen::Vector3d p_world_camera_ = Eigen::Vector3d::Zero();  ///< the camera centre of T_world_camera_
  bool has_state_ = false;
  bool images_changed_ = true;
  double content_transition_ = 0;
  double time_ = 0;
  double background_ = 0;
  std::vector<ProjectedPolygon> projected_;
  std::vector<bool> polygon_convex_;
  std::vector<ProjectedImage> projected_images_;
  std::vector<Eigen::Vector2d> corner_wall_;  ///< wall points of the pixel corners (only with images)
  Eigen::Matrix3d R_world_camera_ = Eigen::Matrix3d::Identity();
  std::vector<Eigen::Vector3d> visible_edge_points_world_;
  std::vector<Eigen::Vector2d> visible_edge_points_px_;
  mutable std::vector<Eigen::Vector2d> scratch_a_, scratch_b_;
};
}  // namespace dvs_screen_sim
