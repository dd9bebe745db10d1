#pragma once
// Event images for people: the accumulated pattern (preview) and the undistorted event image
// that shows whether the calibration straightens lines (thesis Fig. 2.3).
#include <dvs_calibration/camera_model.h>
#include <dvs_driver/event.h>

#include <opencv2/core.hpp>

#include <string>

namespace dvs_calibration
{
/// Counts (CV_32S/CV_32F) -> CV_8U, scaled so the 99th percentile of the non-zero counts is white.
cv::Mat countsToImage(const cv::Mat& counts);

/// Counts (CV_32S/CV_32F, sensor pixels) moved to their undistorted (ideal) pixel positions
/// through the camera's lookup table, splatted bilinearly. CV_32F, same size and K.
cv::Mat undistortCounts(const cv::Mat& counts, const CameraModel& camera);

/// Per-pixel counts of a set of events (CV_32S, width x height; events outside are skipped).
cv::Mat countEvents(const dvs_driver::EventVector& events, int width, int height);

/// Preview: grey counts with the grid detection drawn (if any) and the focus score written. CV_8UC3.
cv::Mat renderPreview(const cv::Mat& counts, const std::vector<cv::Point2f>& grid_centers, int grid_cols,
                      double focus_score, int upscale = 4);
/// Write an image (format from the extension: .png, .jpg, ...) with every failure reported:
/// throws dvs_driver::WriteError naming the file (missing folder, full disk, unknown extension).
void writeImageChecked(const std::string& path, const cv::Mat& image);
}  // namespace dvs_calibration
