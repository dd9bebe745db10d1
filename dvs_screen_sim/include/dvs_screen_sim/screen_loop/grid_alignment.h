#pragma once
// The alignment phase of the screen in the loop (thesis ch. 3.2): a blinking grid of circles
// drawn at known viewport positions, detected in the DVS's events with dvs_calibration's grid
// detector, undistorted, and turned into H_D and the correction H (alignment.h).
#include <dvs_calibration/camera_model.h>
#include <dvs_calibration/event_window.h>
#include <dvs_calibration/grid_detector.h>
#include <dvs_screen_sim/screen_loop/alignment.h>
#include <dvs_screen_sim/screen_loop/projection_pipeline.h>

#include <string>

namespace dvs_screen_sim
{
namespace screen_loop
{
/// The circle grid shown on the screen, in viewport coordinates (x right, y up, [-1, 1]).
struct AlignmentPattern
{
  int cols = 7;
  int rows = 5;
  Eigen::Vector2d centre_vp{0.0, 0.0};
  Eigen::Vector2d spacing_vp{0.2, 0.25};  ///< between neighbouring centres along x and y
  double radius_px = 12.0;                ///< circle radius [window pixels]
  double on_intensity = 1.0;              ///< white circles ...
  double off_intensity = 0.0;             ///< ... on black (also the circles' "off" level)
  int blink_frames = 1;                   ///< screen refreshes per half blink period
  /// Throws std::invalid_argument naming the bad field.
  void validate() const;
};

/// Centres in the detector's layout: index r * cols + c, column c to the right (+x), row r
/// downwards (-y, row 0 at the top).
Points2d patternCentresViewport(const AlignmentPattern& pattern);

struct GridAlignmentConfig
{
  dvs_calibration::DetectorKind detector = dvs_calibration::DetectorKind::Counts;
  dvs_calibration::CountThresholdConfig counts;
  dvs_calibration::BlinkDetectorConfig blink;
  dvs_calibration::GridDetectorConfig grid;  ///< its grid size is taken from the pattern
};

struct GridAlignment
{
  bool ok = false;
  std::string reason;                ///< why not (empty when ok)
  Points2d measured_px;              ///< detected centres (sensor pixels), pattern order
  Points2d measured_ideal_px;        ///< the same, undistorted
  AlignmentResult result;            ///< H_D, H, residual in DVS px
};

/// Detect the pattern in one event window, undistort the centres with `camera`, put them in the
/// pattern's order (the detector's order is defined up to the grid's symmetries: the one that
/// keeps the DVS upright and not mirrored, i.e. image right ~ viewport +x and image down ~
/// viewport -y, is chosen), and compute the alignment (desired positions = A X_vp, Eq. 3.12
/// for circles drawn through the uncorrected pipeline).
GridAlignment alignFromEvents(const dvs_calibration::EventWindow& window, const dvs_calibration::CameraModel& camera,
                              const ProjectionPipeline& pipeline, const AlignmentPattern& pattern,
                              const GridAlignmentConfig& config = GridAlignmentConfig());

/// The ordering step alone: `detected_ideal_px` in the detector's order for a cols x rows grid
/// -> the pattern's order, by the upright/not-mirrored rule above. Exposed for tests.
Points2d orderLikePattern(const Points2d& detected_ideal_px, const AlignmentPattern& pattern,
                          const Eigen::Vector2d& image_centre_px);
}  // namespace screen_loop
}  // namespace dvs_screen_sim
