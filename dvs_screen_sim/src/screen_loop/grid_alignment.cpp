#include <dvs_screen_sim/screen_loop/grid_alignment.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace dvs_screen_sim
{
namespace screen_loop
{
void AlignmentPattern::validate() const
{
  if (cols < 2 || rows < 2)
    throw std::invalid_argument("alignment pattern: cols and rows must be >= 2");
  if (!(spacing_vp.x() > 0) || !(spacing_vp.y() > 0))
    throw std::invalid_argument("alignment pattern: spacing_vp must be positive");
  if (!(radius_px > 0))
    throw std::invalid_argument("alignment pattern: radius_px must be positive");
  if (blink_frames < 1)
    throw std::invalid_argument("alignment pattern: blink_frames must be >= 1");
  const double hx = 0.5 * (cols - 1) * spacing_vp.x(), hy = 0.5 * (rows - 1) * spacing_vp.y();
  if (std::abs(centre_vp.x()) + hx > 1.0 || std::abs(centre_vp.y()) + hy > 1.0)
    throw std::invalid_argument("alignment pattern: the grid does not fit into the viewport [-1, 1]^2");
}

Points2d patternCentresViewport(const AlignmentPattern& p)
{
  Points2d c;
  c.reserve(static_cast<size_t>(p.cols) * p.rows);
  for (int r = 0; r < p.rows; ++r)
    for (int k = 0; k < p.cols; ++k)
      c.emplace_back(p.centre_vp.x() + (k - 0.5 * (p.cols - 1)) * p.spacing_vp.x(),
                     p.centre_vp.y() - (r - 0.5 * (p.rows - 1)) * p.spacing_vp.y());
  return c;
}

Points2d orderLikePattern(const Points2d& detected, const AlignmentPattern& p, const Eigen::Vector2d& image_centre)
{
  const int C = p.cols, R = p.rows;
  if (detected.size() != static_cast<size_t>(C) * R)
    throw AlignmentError("orderLikePattern: " + std::to_string(detected.size()) + " centres for a " +
                         std::to_string(C) + "x" + std::to_string(R) + " grid");
  const Points2d vp = patternCentresViewport(p);
  // Candidate index maps pattern (c, r) -> detector index: the grid's symmetries (the detector
  // reports cols x rows, or rows x cols when it read the grid transposed).
  double best_score = -std::numeric_limits<double>::infinity();
  Points2d best;
  for (int transpose = 0; transpose < 2; ++transpose)
    for (int flip = 0; flip < 4; ++flip)
    {
      Points2d ordered(detected.size());
      for (int r = 0; r < R; ++r)
        for (int c = 0; c < C; ++c)
        {
          int cc = (flip & 1) ? C - 1 - c : c;
          int rr = (flip & 2) ? R - 1 - r : r;
          // Detector index: row-major r * C + c, or the transposed reading c * R + r (a quarter
          // turn of a square grid; for other grids it is no homography and loses on the fit).
          const size_t idx = transpose ? static_cast<size_t>(cc) * R + rr : static_cast<size_t>(rr) * C + cc;
          ordered[static_cast<size_t>(r) * C + c] = detected[idx];
        }
      Eigen::Matrix3d H_D;
      try
      {
        H_D = fitHomography(ordered, vp);
      }
      catch (const AlignmentError&)
      {
        continue;
      }
      const Eigen::Vector2d o = applyHomography(H_D, image_centre);
      const Eigen::Vector2d ex = applyHomography(H_D, image_centre + Eigen::Vector2d(5, 0)) - o;
      const Eigen::Vector2d ey = applyHomography(H_D, image_centre + Eigen::Vector2d(0, 5)) - o;
      if (!ex.allFinite() || !ey.allFinite() || ex.norm() == 0 || ey.norm() == 0)
        continue;
      // Fit quality first (a wrong transposition of a non-square grid is not a homography),
      // then the upright rule.
      const double rms = transferError(H_D, ordered, vp).rms;
      const double upright = ex.normalized().x() - ey.normalized().y();  // in [-2, 2]
      const double score = upright - 100.0 * rms / (p.spacing_vp.norm());
      if (score > best_score)
      {
        best_score = score;
        best = ordered;
      }
    }
  if (best.empty())
    throw AlignmentError("orderLikePattern: no ordering of the detected centres gives a homography");
  return best;
}

GridAlignment alignFromEvents(const dvs_calibration::EventWindow& window, const dvs_calibration::CameraModel& camera,
                              const ProjectionPipeline& pipeline, const AlignmentPattern& pattern,
                              const GridAlignmentConfig& config)
{
  pattern.validate();
  GridAlignment out;
  dvs_calibration::GridDetectorConfig grid = config.grid;
  grid.grid.cols = pattern.cols;
  grid.grid.rows = pattern.rows;
  const auto wd = dvs_calibration::detectGridInWindow(window, config.detector, config.counts, config.blink, grid);
  if (!wd.detection.found)
  {
    out.reason = "circle grid not found in the events: " + wd.detection.reason;
    return out;
  }
  Points2d ideal;
  for (const auto& c : wd.detection.centers)
    ideal.push_back(camera.undistortPixel(Eigen::Vector2d(c.x, c.y)));
  const Eigen::Vector2d image_centre(0.5 * (camera.width() - 1), 0.5 * (camera.height() - 1));
  try
  {
    out.measured_ideal_px = orderLikePattern(ideal, pattern, image_centre);
    for (const auto& q : out.measured_ideal_px)
      out.measured_px.push_back(camera.distortPixel(q));
    const Points2d vp = patternCentresViewport(pattern);
    Points2d desired;
    const Eigen::Matrix3d A = pipeline.viewportToIdealDvs();
    for (const auto& v : vp)
      desired.push_back(applyHomography(A, v));
    out.result = computeAlignment(out.measured_ideal_px, vp, desired);
    out.ok = true;
  }
  catch (const AlignmentError& e)
  {
    out.reason = e.what();
  }
  return out;
}
}  // namespace screen_loop
}  // namespace dvs_screen_sim
