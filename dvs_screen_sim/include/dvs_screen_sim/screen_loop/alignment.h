#pragma once
// Misalignment correction between the DVS and the screen (thesis ch. 3.2, Eq. 3.11-3.14).
//
//   H_D   : ideal (undistorted) DVS pixel -> viewport, fitted to the detected circle centres
//           and the viewport positions they were drawn at (Eq. 3.11).
//   X'_D  : where the circles should appear in the DVS: the circles' world points projected with
//           the DVS intrinsics from the virtual camera's pose (Eq. 3.12); for circles drawn
//           through the uncorrected pipeline this is A X_vp (ProjectionPipeline::viewportToIdealDvs).
//   X'_vp = H_D X'_D (Eq. 3.13): where they must be drawn for the DVS to see them there.
//   H     : X_vp -> X'_vp (Eq. 3.14), the correction applied to clip coordinates (Eq. 3.15).
// The residual of H_D (measured centres vs H_D^-1 X_vp) is reported in DVS pixels.
#include <Eigen/Core>

#include <stdexcept>
#include <vector>

namespace dvs_screen_sim
{
namespace screen_loop
{
class AlignmentError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

using Points2d = std::vector<Eigen::Vector2d>;

/// Least-squares homography dst ~ H src from >= 4 correspondences: normalised DLT (Hartley),
/// then Gauss-Newton on the transfer error in dst. Throws AlignmentError for fewer than 4
/// points, mismatched sizes, non-finite points or a degenerate (collinear) configuration.
Eigen::Matrix3d fitHomography(const Points2d& src, const Points2d& dst);

/// RMS and mean of |H src_i - dst_i|.
struct TransferError
{
  double rms = 0;
  double mean = 0;
  double max = 0;
};
TransferError transferError(const Eigen::Matrix3d& H, const Points2d& src, const Points2d& dst);

struct AlignmentResult
{
  Eigen::Matrix3d H_D = Eigen::Matrix3d::Identity();  ///< ideal DVS px -> viewport (Eq. 3.11)
  Eigen::Matrix3d H = Eigen::Matrix3d::Identity();    ///< viewport -> corrected viewport (Eq. 3.14)
  /// |measured centre - H_D^-1 X_vp| in ideal DVS pixels: how well a homography explains the
  /// detections (lens distortion left over, detection noise).
  TransferError residual_dvs_px;
  size_t points = 0;
};

/// Eq. 3.11-3.14. `measured_ideal_px`: detected circle centres in the DVS, undistorted (ideal
/// pixels); `displayed_vp`: the viewport positions they were drawn at (same order);
/// `desired_ideal_px`: where the DVS should see them (Eq. 3.12, same order).
AlignmentResult computeAlignment(const Points2d& measured_ideal_px, const Points2d& displayed_vp,
                                 const Points2d& desired_ideal_px);
}  // namespace screen_loop
}  // namespace dvs_screen_sim
