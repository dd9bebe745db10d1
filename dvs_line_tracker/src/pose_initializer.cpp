#include <dvs_line_tracker/pose_initializer.h>

#include <Eigen/Geometry>
#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dvs_line_tracker
{
namespace
{
/// The ideal pixel (u, v) of world point `world` at the pose (angle-axis aa, translation t).
template <typename T>
void projectToPixel(const T* const aa, const T* const t, const Eigen::Vector3d& world, const PinholeK& k, T& u, T& v)
{
  const T pw[3] = {T(world.x()), T(world.y()), T(world.z())};
  T pc[3];
  ceres::AngleAxisRotatePoint(aa, pw, pc);
  pc[0] += t[0];
  pc[1] += t[1];
  pc[2] += t[2];
  u = T(k.fx) * pc[0] / pc[2] + T(k.cx);
  v = T(k.fy) * pc[1] / pc[2] + T(k.cy);
}

struct CornerReprojection
{
  CornerReprojection(const Eigen::Vector2d& obs, const Eigen::Vector3d& world, const PinholeK& k)
    : obs_(obs), world_(world), k_(k)
  {
  }
  template <typename T>
  bool operator()(const T* const aa, const T* const t, T* residual) const
  {
    T u, v;
    projectToPixel(aa, t, world_, k_, u, v);
    residual[0] = u - T(obs_.x());
    residual[1] = v - T(obs_.y());
    return true;
  }
  Eigen::Vector2d obs_;
  Eigen::Vector3d world_;
  PinholeK k_;
};

/// A map point whose projection must lie on an image line n.x = d (n unit): one residual.
struct PointOnLine
{
  PointOnLine(const Eigen::Vector2d& normal, double d, const Eigen::Vector3d& world, const PinholeK& k)
    : normal_(normal), d_(d), world_(world), k_(k)
  {
  }
  template <typename T>
  bool operator()(const T* const aa, const T* const t, T* residual) const
  {
    T u, v;
    projectToPixel(aa, t, world_, k_, u, v);
    residual[0] = T(normal_.x()) * u + T(normal_.y()) * v - T(d_);
    return true;
  }
  Eigen::Vector2d normal_;
  double d_;
  Eigen::Vector3d world_;
  PinholeK k_;
};

/// A pose as Ceres parameters: angle-axis rotation and translation (world -> camera).
void poseToParameters(const Pose& pose, double aa[3], double t[3])
{
  const Eigen::AngleAxisd angle_axis(pose.R_camera_world);
  const Eigen::Vector3d aav = angle_axis.angle() * angle_axis.axis();
  for (int i = 0; i < 3; ++i)
  {
    aa[i] = aav[i];
    t[i] = pose.t_camera_world[i];
  }
}

/// Solve `problem` over (aa, t) silently; the pose they hold after it into `out`. False when
/// that pose is not finite.
bool solvePose(ceres::Problem& problem, double aa[3], double t[3], int iterations, ceres::Solver::Summary& summary,
               Pose& out)
{
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = iterations;
  options.logging_type = ceres::SILENT;
  ceres::Solve(options, &problem, &summary);
  const Eigen::Vector3d w(aa[0], aa[1], aa[2]);
  out.R_camera_world = w.norm() > 1e-12 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix()
                                        : Eigen::Matrix3d::Identity();
  out.t_camera_world = Eigen::Vector3d(t[0], t[1], t[2]);
  return out.R_camera_world.allFinite() && out.t_camera_world.allFinite();
}

/// The image line through a and b as (unit normal, offset).
void lineThrough(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Eigen::Vector2d& normal, double& d)
{
  const Eigen::Vector2d dir = (b - a).normalized();
  normal = Eigen::Vector2d(-dir.y(), dir.x());
  d = normal.dot(a);
}

/// The pose of OpenCV's rotation matrix and translation (world -> camera).
Pose poseFromCv(const cv::Matx33d& R, const double* t)
{
  Pose pose;
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
      pose.R_camera_world(r, c) = R(r, c);
    pose.t_camera_world[r] = t[r];
  }
  return pose;
}

/// Map polygons are listed counter-clockwise seen from the side they are viewed from.
bool viewedFromFront(const MapPolygon& poly, const Pose& pose)
{
  return frontNormal(poly).dot(pose.p_world_camera() - cornerCentroid(poly)) >= 0;
}

/// The pose of one corner assignment: IPPE for planar polygons (`planar_ippe`); it degenerates
/// (NaN) for exactly fronto-parallel views, where SQPnP takes over (and for non-planar ones).
/// SQPnP is a global search about ten times IPPE's cost: it runs only when IPPE gave no pose
/// that fits the corners (within `max_rms_px`). Returns the corner reprojection RMS of `pose`
/// (infinite: no pose).
double solveAssignment(const std::vector<Eigen::Vector3d>& world, const std::vector<cv::Point2d>& image_cv,
                       const cv::Matx33d& K, bool planar_ippe, const PinholeK& k,
                       const std::vector<Eigen::Vector2d>& corners_ideal_px, double max_rms_px, Pose& pose)
{
  std::vector<cv::Point3d> world_cv;
  for (const auto& w : world)
    world_cv.emplace_back(w.x(), w.y(), w.z());
  double rms = std::numeric_limits<double>::infinity();
  for (const int method : {cv::SOLVEPNP_IPPE, cv::SOLVEPNP_SQPNP})
  {
    if (method == cv::SOLVEPNP_IPPE && !planar_ippe)
      continue;
    cv::Vec3d rvec, tvec;
    bool ok = false;
    try
    {
      ok = cv::solvePnP(world_cv, image_cv, K, cv::noArray(), rvec, tvec, false, method);
    }
    catch (const cv::Exception&)
    {
      ok = false;
    }
    if (!ok || !std::isfinite(rvec[0] + rvec[1] + rvec[2] + tvec[0] + tvec[1] + tvec[2]))
      continue;
    cv::Matx33d Rcv;
    cv::Rodrigues(rvec, Rcv);
    const Pose candidate = poseFromCv(Rcv, tvec.val);
    const double candidate_rms = cornerReprojectionRms(candidate, k, corners_ideal_px, world);
    if (candidate_rms < rms)
    {
      rms = candidate_rms;
      pose = candidate;
    }
    if (rms <= max_rms_px)
      break;
  }
  return rms;
}

/// The rigid motion S with S * from[i] = to[i] for every i (within 1e-9 of the points' extent);
/// false when there is none. A planar polygon's corners in another order are such an image of
/// themselves when the order is one of the polygon's symmetries: a square's quarter turns, and
/// its reversed orders (a half turn about an axis in its plane).
bool rigidMotionBetween(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                        Eigen::Isometry3d& S)
{
  const int n = static_cast<int>(from.size());
  if (n < 3 || to.size() != from.size())
    return false;
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (int i = 0; i < n; ++i)
  {
    src.col(i) = from[i];
    dst.col(i) = to[i];
  }
  S.matrix() = Eigen::umeyama(src, dst, false);
  const Eigen::Vector3d centroid = src.rowwise().mean();
  const double extent = std::max((src.colwise() - centroid).colwise().norm().maxCoeff(), 1.0);
  for (int i = 0; i < n; ++i)
    if (!((S * from[i] - to[i]).norm() <= 1e-9 * extent))
      return false;
  return std::abs(S.linear().determinant() - 1.0) < 1e-9;
}

/// The camera pose that sees S * x where `pose` sees x (pose * S^-1).
Pose composedWithInverse(const Pose& pose, const Eigen::Isometry3d& S)
{
  Pose out;
  out.R_camera_world = pose.R_camera_world * S.linear().transpose();
  out.t_camera_world = pose.t_camera_world - out.R_camera_world * S.translation();
  return out;
}
}  // namespace

double upScore(const Pose& pose, const PinholeK& k, const std::vector<Eigen::Vector3d>& world,
               const Eigen::Vector3d& up)
{
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double size = 0;
  for (const auto& p : world)
    centre += p;
  centre /= static_cast<double>(world.size());
  for (const auto& p : world)
    size = std::max(size, (p - centre).norm());
  const Eigen::Vector3d a = pose.toCamera(centre), b = pose.toCamera(centre + 0.1 * size * up);
  if (a.z() <= 0 || b.z() <= 0)
    return -1;
  const Eigen::Vector2d v = k.project(b) - k.project(a);
  if (v.norm() < 1e-6)
    return 0;
  return -v.y() / v.norm();
}

double cornerReprojectionRms(const Pose& pose, const PinholeK& k, const std::vector<Eigen::Vector2d>& image,
                             const std::vector<Eigen::Vector3d>& world)
{
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i)
  {
    const Eigen::Vector3d pc = pose.toCamera(world[i]);
    if (pc.z() <= 1e-6)
      return std::numeric_limits<double>::infinity();
    sum += (k.project(pc) - image[i]).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(image.size()));
}

Pose refinePoseReprojection(const Pose& initial, const PinholeK& k,
                                  const std::vector<Eigen::Vector2d>& image, const std::vector<Eigen::Vector3d>& world)
{
  double aa[3], t[3];
  poseToParameters(initial, aa, t);
  ceres::Problem problem;
  for (size_t i = 0; i < image.size(); ++i)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<CornerReprojection, 2, 3, 3>(
                                 new CornerReprojection(image[i], world[i], k)),
                             nullptr, aa, t);
  ceres::Solver::Summary summary;
  Pose out;
  return solvePose(problem, aa, t, 20, summary, out) ? out : initial;
}

namespace
{
/// Refine `pose` so that the open polygon's corners in view reproject onto theirs (`world_known`)
/// and the two missing map corners onto their outer sides' lines; the fit's RMS (px) into `rms`.
Pose refineOpen(const Pose& initial, const PinholeK& k, const ImagePolygon& open,
                const std::vector<Eigen::Vector3d>& world_known, const Eigen::Vector3d& world_first,
                const Eigen::Vector3d& world_last, double& rms)
{
  double aa[3], t[3];
  poseToParameters(initial, aa, t);
  ceres::Problem problem;
  for (size_t i = 0; i < open.corners.size(); ++i)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<CornerReprojection, 2, 3, 3>(
                                 new CornerReprojection(open.corners[i], world_known[i], k)),
                             nullptr, aa, t);
  Eigen::Vector2d n_first, n_last;
  double d_first, d_last;
  lineThrough(open.open_first, open.corners.front(), n_first, d_first);
  lineThrough(open.corners.back(), open.open_last, n_last, d_last);
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointOnLine, 1, 3, 3>(
                               new PointOnLine(n_first, d_first, world_first, k)),
                           nullptr, aa, t);
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PointOnLine, 1, 3, 3>(
                               new PointOnLine(n_last, d_last, world_last, k)),
                           nullptr, aa, t);
  ceres::Solver::Summary summary;
  Pose out;
  rms = std::numeric_limits<double>::infinity();
  if (!solvePose(problem, aa, t, 30, summary, out) || !summary.IsSolutionUsable())
    return initial;
  const int residuals = 2 * static_cast<int>(open.corners.size()) + 2;
  rms = std::sqrt(2.0 * summary.final_cost / residuals);
  return out;
}
}  // namespace

bool estimateInitialPoseOpen(const ImagePolygon& open, const LineMap& map, const PinholeK& k,
                             const PoseInitParams& params, InitialPose& result, int only_polygon)
{
  const int n = static_cast<int>(open.corners.size()) + 2;
  if (!open.open || n < 4 || (open.open_first - open.corners.front()).norm() < 1e-6 ||
      (open.open_last - open.corners.back()).norm() < 1e-6)
    return false;
  bool found = false;
  for (size_t pi = 0; pi < map.polygons.size(); ++pi)
  {
    const MapPolygon& poly = map.polygons[pi];
    if (static_cast<int>(poly.corners_world.size()) != n || (only_polygon >= 0 && static_cast<int>(pi) != only_polygon))
      continue;
    // Completed corners c[0..n-1]: c[1..n-2] in view, c[0] and c[n-1] on the outer sides at the
    // mean length of the sides in view (the assignment, and so the map's side ratios, is
    // chosen by estimateInitialPose on these corners: a guess, refined below).
    double inner_px = 0;
    for (size_t i = 0; i + 1 < open.corners.size(); ++i)
      inner_px += (open.corners[i + 1] - open.corners[i]).norm();
    const double side_px = inner_px / static_cast<double>(open.corners.size() - 1);  // n >= 4: >= 2 corners
    if (side_px <= 0)  // coincident corners
      continue;
    std::vector<Eigen::Vector2d> completed;
    completed.push_back(open.corners.front() + (open.open_first - open.corners.front()).normalized() * side_px);
    completed.insert(completed.end(), open.corners.begin(), open.corners.end());
    completed.push_back(open.corners.back() + (open.open_last - open.corners.back()).normalized() * side_px);
    PoseInitParams loose = params;
    loose.max_reprojection_rms_px = std::max(params.max_reprojection_rms_px, 0.25 * side_px);
    loose.refine = false;
    InitialPose guess;
    if (!estimateInitialPose(completed, map, k, loose, guess, static_cast<int>(pi)))
      continue;
    std::vector<Eigen::Vector3d> world_known;
    for (int i = 1; i + 1 < n; ++i)
      world_known.push_back(poly.corners_world[guess.corner_assignment[i]]);
    const Eigen::Vector3d& world_first = poly.corners_world[guess.corner_assignment[0]];
    const Eigen::Vector3d& world_last = poly.corners_world[guess.corner_assignment[n - 1]];
    // The missing side lies beyond the outer sides' detected ends (else it would be in view).
    auto beyondEnds = [&](const Pose& pose) {
      const Eigen::Vector3d a = pose.toCamera(world_first), b = pose.toCamera(world_last);
      if (a.z() <= 1e-6 || b.z() <= 1e-6)
        return false;
      const Eigen::Vector2d fa = k.project(a), lb = k.project(b);
      const Eigen::Vector2d u_first = (open.open_first - open.corners.front()).normalized();
      const Eigen::Vector2d u_last = (open.open_last - open.corners.back()).normalized();
      constexpr double kSlackPx = 3.0;
      return (fa - open.corners.front()).dot(u_first) >= (open.open_first - open.corners.front()).norm() - kSlackPx &&
             (lb - open.corners.back()).dot(u_last) >= (open.open_last - open.corners.back()).norm() - kSlackPx;
    };
    std::vector<Pose> starts{guess.pose};
    starts.insert(starts.end(), guess.alternatives.begin(), guess.alternatives.end());
    InitialPose out;
    bool have = false;
    for (const Pose& start : starts)
    {
      double rms = 0;
      const Pose pose = refineOpen(start, k, open, world_known, world_first, world_last, rms);
      if (!(rms <= params.max_reprojection_rms_px) || !viewedFromFront(poly, pose) || !beyondEnds(pose))
        continue;
      auto same = [&](const Pose& f) { return posesAgree(f, pose, 0.01, 1.0); };
      if (have && (same(out.pose) || std::any_of(out.alternatives.begin(), out.alternatives.end(), same)))
        continue;
      if (!have)
      {
        have = true;
        out = guess;
        out.pose = pose;
        out.reprojection_rms_px = rms;
        out.alternatives.clear();
      }
      else
        out.alternatives.push_back(pose);
    }
    if (!have)
      continue;
    if (!found || out.up_score > result.up_score + 1e-6)
    {
      found = true;
      result = out;
    }
  }
  return found;
}

bool estimateInitialPose(const std::vector<Eigen::Vector2d>& corners_ideal_px, const LineMap& map, const PinholeK& k,
                         const PoseInitParams& params, InitialPose& result, int only_polygon)
{
  const int n = static_cast<int>(corners_ideal_px.size());
  if (n < 3)
    return false;
  const cv::Matx33d K(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  std::vector<cv::Point2d> image_cv;
  for (const auto& c : corners_ideal_px)
    image_cv.emplace_back(c.x(), c.y());

  bool found = false;
  InitialPose best;
  // Every assignment that fits, for the up-margin (a symmetric polygon fits several).
  struct Fitting
  {
    Pose pose;
    double up_score;
    int polygon;
    bool front;  ///< sees the polygon from the front
  };
  std::vector<Fitting> fitting;
  for (size_t pi = 0; pi < map.polygons.size(); ++pi)
  {
    const MapPolygon& poly = map.polygons[pi];
    if (static_cast<int>(poly.corners_world.size()) != n || (only_polygon >= 0 && static_cast<int>(pi) != only_polygon))
      continue;
    // An assignment whose corners are a rigid motion S of an assignment solved before (the
    // polygon's symmetries: a square's quarter turns and reversed orders) fits exactly as that
    // one does, moved by S: its pose is derived, not solved again (a square: 1 solve instead of
    // 8; the solves were most of a noisy scene's detection attempts, BENCHMARKS.md).
    struct Solved
    {
      std::vector<Eigen::Vector3d> world;
      Pose pose;
      bool posed;  ///< the solve gave a pose (fitting or not)
    };
    std::vector<Solved> solved;
    for (int direction = 0; direction < 2; ++direction)
      for (int shift = 0; shift < n; ++shift)
      {
        std::vector<int> assignment(n);
        std::vector<Eigen::Vector3d> world;
        for (int i = 0; i < n; ++i)
        {
          assignment[i] = direction == 0 ? (shift + i) % n : (shift - i + n) % n;
          world.push_back(poly.corners_world[assignment[i]]);
        }
        Pose pose;
        double rms = std::numeric_limits<double>::infinity();
        Eigen::Isometry3d S;
        const auto image_of = std::find_if(solved.begin(), solved.end(),
                                           [&](const Solved& e) { return rigidMotionBetween(e.world, world, S); });
        if (image_of != solved.end())
        {
          if (!image_of->posed)
            continue;
          pose = composedWithInverse(image_of->pose, S);
          rms = cornerReprojectionRms(pose, k, corners_ideal_px, world);
        }
        else
        {
          rms = solveAssignment(world, image_cv, K, poly.planar && n >= 4, k, corners_ideal_px,
                                params.max_reprojection_rms_px, pose);
          solved.push_back({world, pose, std::isfinite(rms)});
        }
        if (!(rms <= params.max_reprojection_rms_px))
          continue;
        // Map polygons are listed counter-clockwise seen from the side they are viewed from:
        // a camera behind the polygon (a mirrored solution) is heavily penalised.
        const bool front = !(poly.planar && n >= 3) || viewedFromFront(poly, pose);
        double score = upScore(pose, k, world, map.up_world);
        if (!front)
          score -= 10.0;
        fitting.push_back({pose, score, static_cast<int>(pi), front});
        const bool better = !found || score > best.up_score + 1e-6 ||
                            (std::abs(score - best.up_score) <= 1e-6 && rms < best.reprojection_rms_px);
        if (better)
        {
          found = true;
          best.pose = pose;
          best.reprojection_rms_px = rms;
          best.up_score = score;
          best.polygon_index = static_cast<int>(pi);
          best.corner_assignment = assignment;
        }
      }
  }
  if (!found)
    return false;
  std::stable_sort(fitting.begin(), fitting.end(), [](const Fitting& a, const Fitting& b) { return a.up_score > b.up_score; });
  for (const Fitting& f : fitting)
    if (f.polygon == best.polygon_index && !sameHypothesis(best.pose, f.pose))
    {
      best.up_margin = std::min(best.up_margin, best.up_score - f.up_score);
      if (f.front && std::none_of(best.rotations.begin(), best.rotations.end(), [&](const Pose& r) { return sameHypothesis(r, f.pose); }))
        best.rotations.push_back(f.pose);
    }
  const MapPolygon& chosen = map.polygons[best.polygon_index];
  if (chosen.planar && n >= 3)
  {
    std::vector<cv::Point3d> world_cv;
    for (int i = 0; i < n; ++i)
    {
      const Eigen::Vector3d& w = chosen.corners_world[best.corner_assignment[i]];
      world_cv.emplace_back(w.x(), w.y(), w.z());
    }
    std::vector<cv::Mat> rvecs, tvecs;
    try
    {
      if (n == 3)
        cv::solveP3P(world_cv, image_cv, K, cv::noArray(), rvecs, tvecs, cv::SOLVEPNP_P3P);
      else
        cv::solvePnPGeneric(world_cv, image_cv, K, cv::noArray(), rvecs, tvecs, false, cv::SOLVEPNP_IPPE);
    }
    catch (const cv::Exception&)
    {
      rvecs.clear();
    }
    std::vector<Eigen::Vector3d> world;
    for (int i = 0; i < n; ++i)
      world.push_back(chosen.corners_world[best.corner_assignment[i]]);
    for (size_t si = 0; si < rvecs.size() && si < tvecs.size(); ++si)
    {
      cv::Mat rv, tv;
      rvecs[si].convertTo(rv, CV_64F);
      tvecs[si].convertTo(tv, CV_64F);
      if (rv.total() != 3 || tv.total() != 3 || !cv::checkRange(rv) || !cv::checkRange(tv))
        continue;
      cv::Matx33d Rcv;
      cv::Rodrigues(rv, Rcv);
      const Pose twin = poseFromCv(Rcv, tv.ptr<double>());
      if (!posesAgree(twin, best.pose, 0.01, 1.0) && viewedFromFront(chosen, twin) &&
          cornerReprojectionRms(twin, k, corners_ideal_px, world) <= params.max_reprojection_rms_px)
        best.alternatives.push_back(twin);
    }
  }
  if (params.refine)
  {
    std::vector<Eigen::Vector3d> world;
    for (int i = 0; i < n; ++i)
      world.push_back(map.polygons[best.polygon_index].corners_world[best.corner_assignment[i]]);
    const Pose refined = refinePoseReprojection(best.pose, k, corners_ideal_px, world);
    const double rms = cornerReprojectionRms(refined, k, corners_ideal_px, world);
    if (rms <= best.reprojection_rms_px + 1e-9)
    {
      best.pose = refined;
      best.reprojection_rms_px = rms;
    }
  }
  result = best;
  return true;
}
}  // namespace dvs_line_tracker
