// Known answers for the per-event pose estimator: analytic Jacobians against numerical ones,
// and convergence to the true pose from exact points on the projected segments.
#include <dvs_line_tracker/pose_estimator.h>
#include "synthetic_events.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

using namespace dvs_line_tracker;

namespace
{
PinholeK dvs128K() { return PinholeK{115, 115, 63.5, 63.5}; }

std::vector<SegmentBuffer> exactBuffers(const LineMap& map, const Pose& pose, const PinholeK& k, int n)
{
  std::vector<SegmentBuffer> buffers;
  for (const auto& s : map.segments)
  {
    SegmentBuffer b(n);
    ProjectedSegment ps;
    ps.set(k.project(pose.toCamera(s.p0_world)), k.project(pose.toCamera(s.p1_world)));
    for (int i = 0; i < n; ++i)
    {
      // Points on the 3D segment, projected (exact).
      const double f = (i + 0.5) / n;
      b.insert(k.project(pose.toCamera(s.p0_world + f * (s.p1_world - s.p0_world))), ps);
    }
    buffers.push_back(b);
  }
  return buffers;
}
}  // namespace

TEST(PoseEstimator, ProjectionJacobianMatchesNumerical)
{
  const PinholeK k = dvs128K();
  const Pose pose = lookAt({0.2, -0.1, 1.5}, {0, 0, 0}, {0, 1, 0}, 0.3);
  const Eigen::Vector3d p_world(0.3, 0.4, 0.05);
  // Both rows of the 2x6 Jacobian (n = x, y) and a diagonal direction.
  Vector6d jx, jy, jd;
  const Eigen::Vector2d diagonal = Eigen::Vector2d(1, 1).normalized();
  projectAlongNormal(k, pose.toCamera(p_world), Eigen::Vector2d::UnitX(), jx);
  projectAlongNormal(k, pose.toCamera(p_world), Eigen::Vector2d::UnitY(), jy);
  projectAlongNormal(k, pose.toCamera(p_world), diagonal, jd);
  for (int d = 0; d < 6; ++d)
  {
    Vector6d delta = Vector6d::Zero();
    delta[d] = 1e-6;
    Pose plus = pose, minus = pose;
    plus.applyCameraIncrement(delta);
    minus.applyCameraIncrement(-delta);
    const Eigen::Vector2d num = (k.project(plus.toCamera(p_world)) - k.project(minus.toCamera(p_world))) / 2e-6;
    EXPECT_NEAR(num.x(), jx[d], 1e-4 * (1 + std::abs(num.x())));
    EXPECT_NEAR(num.y(), jy[d], 1e-4 * (1 + std::abs(num.y())));
    EXPECT_NEAR(diagonal.dot(num), jd[d], 1e-4 * (1 + std::abs(diagonal.dot(num))));
  }
}

TEST(PoseEstimator, SegmentGradientMatchesNumericalCost)
{
  const PinholeK k = dvs128K();
  const LineMap map = defaultSquareMap();
  const Pose truth = lookAt({0.1, 0.05, 1.6}, {0, 0, 0}, {0, 1, 0}, 0.2);
  auto buffers = exactBuffers(map, truth, k, 8);
  Pose pose = truth;
  Vector6d off;
  off << 0.01, -0.02, 0.015, 0.02, -0.01, 0.03;
  pose.applyCameraIncrement(off);
  SegmentNormalEquations eq;
  ASSERT_TRUE(linearizeSegment(k, pose, map.segments[1].p0_world, map.segments[1].p1_world, buffers[1], eq));
  auto cost = [&](const Pose& p) {
    SegmentNormalEquations e;
    linearizeSegment(k, p, map.segments[1].p0_world, map.segments[1].p1_world, buffers[1], e);
    return 0.5 * e.sum_sq;
  };
  for (int d = 0; d < 6; ++d)
  {
    Vector6d delta = Vector6d::Zero();
    delta[d] = 1e-7;
    Pose plus = pose, minus = pose;
    plus.applyCameraIncrement(delta);
    minus.applyCameraIncrement(-delta);
    const double num = (cost(plus) - cost(minus)) / 2e-7;
    EXPECT_NEAR(num, eq.g[d], 1e-3 * (1 + std::abs(num))) << "dimension " << d;
  }
}

TEST(PoseEstimator, GaussNewtonConvergesToTruthFromExactPoints)
{
  const PinholeK k = dvs128K();
  const LineMap map = defaultSquareMap();
  const Pose truth = lookAt({0.1, 0.05, 1.6}, {0, 0, 0}, {0, 1, 0}, 0.2);
  auto buffers = exactBuffers(map, truth, k, 8);
  Pose pose = truth;
  Vector6d off;
  off << 0.01, -0.02, 0.015, 0.02, -0.01, 0.03;
  pose.applyCameraIncrement(off);
  Vector6d x = Vector6d::Zero();
  std::vector<SegmentNormalEquations> eqs(4);
  for (int it = 0; it < 10; ++it)
  {
    for (int i = 0; i < 4; ++i)
    {
      eqs[i].active = linearizeSegment(k, pose, map.segments[i].p0_world, map.segments[i].p1_world, buffers[i],
                                       eqs[i]);
      eqs[i].x_lin = x;
    }
    Vector6d delta;
    ASSERT_TRUE(solveStep(eqs.data(), 4, x, 1e-6, delta));
    pose.applyCameraIncrement(delta);
    x += delta;
  }
  EXPECT_LT(positionError(pose, truth), 1e-6);
  EXPECT_LT(orientationError(pose, truth), 1e-6);
}

TEST(PoseEstimator, SolveStepSolvesTheDampedNormalEquations)
{
  // Known answer: the step of two segments' equations (one linearised at another increment)
  // against Eigen's LDLT of the damped sum; and no step from an indefinite or empty system.
  std::vector<SegmentNormalEquations> eqs(2);
  for (int i = 0; i < 2; ++i)
  {
    const Matrix6d a = Matrix6d::Random();
    eqs[i].H = a * a.transpose() + 0.5 * Matrix6d::Identity();
    eqs[i].g = Vector6d::Random();
    eqs[i].active = true;
  }
  eqs[1].x_lin = 0.01 * Vector6d::Random();
  const Vector6d x_now = 0.02 * Vector6d::Random();
  const double damping = 0.07;
  Matrix6d H = eqs[0].H + eqs[1].H;
  const Vector6d g = eqs[0].g + eqs[1].g + eqs[0].H * x_now + eqs[1].H * (x_now - eqs[1].x_lin);
  H.diagonal().array() *= 1.0 + damping;
  H.diagonal().array() += 1e-9;
  const Vector6d expected = -H.ldlt().solve(g);
  Vector6d delta;
  ASSERT_TRUE(solveStep(eqs.data(), 2, x_now, damping, delta));
  EXPECT_LT((delta - expected).norm(), 1e-10 * expected.norm());

  eqs[0].H = -Matrix6d::Identity();
  EXPECT_FALSE(solveStep(eqs.data(), 1, x_now, damping, delta));
  eqs[0].active = eqs[1].active = false;
  EXPECT_FALSE(solveStep(eqs.data(), 2, x_now, damping, delta));
}

TEST(PoseEstimator, AFactorServesTheStepsOfLaterGradients)
{
  // The factor of the damped information solves for any later gradient (known answer against
  // Eigen's LLT); the parts give solveStep's step bit for bit; an indefinite or empty system
  // leaves the factor invalid, and an invalid factor gives no step.
  std::vector<SegmentNormalEquations> eqs(3);
  for (int i = 0; i < 3; ++i)
  {
    const Matrix6d a = Matrix6d::Random();
    eqs[i].H = a * a.transpose() + 0.1 * Matrix6d::Identity();
    eqs[i].g = Vector6d::Random();
    eqs[i].x_lin = 0.01 * Vector6d::Random();
    eqs[i].active = true;
  }
  eqs[2].active = false;  // an inactive segment counts in neither the factor nor the gradient
  const double damping = 0.07;
  Matrix6d H = eqs[0].H + eqs[1].H;
  H.diagonal().array() *= 1.0 + damping;
  H.diagonal().array() += 1e-9;
  DampedFactor f;
  ASSERT_TRUE(factorDampedInformation(eqs.data(), 3, damping, f));
  ASSERT_TRUE(f.valid);
  for (int trial = 0; trial < 3; ++trial)
  {
    const Vector6d x_now = 0.02 * Vector6d::Random();
    Vector6d g;
    ASSERT_TRUE(gradientAt(eqs.data(), 3, x_now, g));
    const Vector6d g_expected = eqs[0].g + eqs[1].g + eqs[0].H * (x_now - eqs[0].x_lin) + eqs[1].H * (x_now - eqs[1].x_lin);
    EXPECT_LT((g - g_expected).norm(), 1e-12 * g_expected.norm());
    Vector6d delta, whole;
    ASSERT_TRUE(solveWithFactor(f, g, delta));
    const Vector6d expected = -H.llt().solve(g);
    EXPECT_LT((delta - expected).norm(), 1e-10 * expected.norm());
    ASSERT_TRUE(solveStep(eqs.data(), 3, x_now, damping, whole));
    EXPECT_EQ(whole, delta);
  }
  // The summed information carries the gradient to any later point: g(x + d) = g(x) + H d (the
  // held steps of the updater take it so, one 6x6 product per step).
  {
    const Vector6d x_now = 0.02 * Vector6d::Random(), d = 0.01 * Vector6d::Random();
    Vector6d g, g_same, g_moved;
    Matrix6d information;
    ASSERT_TRUE(gradientAndInformationAt(eqs.data(), 3, x_now, g, information));
    ASSERT_TRUE(gradientAt(eqs.data(), 3, x_now, g_same));
    EXPECT_EQ(g, g_same);
    EXPECT_LT((information - (eqs[0].H + eqs[1].H)).norm(), 1e-12 * information.norm());
    ASSERT_TRUE(gradientAt(eqs.data(), 3, x_now + d, g_moved));
    EXPECT_LT((g + information * d - g_moved).norm(), 1e-12 * g_moved.norm());
  }
  eqs[0].H = -4.0 * Matrix6d::Identity();
  EXPECT_FALSE(factorDampedInformation(eqs.data(), 2, damping, f));
  EXPECT_FALSE(f.valid);
  Vector6d delta;
  EXPECT_FALSE(solveWithFactor(f, Vector6d::Ones(), delta));
  eqs[0].active = eqs[1].active = false;
  EXPECT_FALSE(factorDampedInformation(eqs.data(), 3, damping, f));
  Vector6d g;
  EXPECT_FALSE(gradientAt(eqs.data(), 3, Vector6d::Zero(), g));
  Matrix6d information;
  EXPECT_FALSE(gradientAndInformationAt(eqs.data(), 3, Vector6d::Zero(), g, information));
}
