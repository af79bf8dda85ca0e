// The analytic Jacobians of the height difference error against numerical differentiation.
#include <gtest/gtest.h>

#include <random>

#include "dlo/core/height_frame.h"
#include "dlo/core/height_residual.h"
#include "dlo/core/rigid_transform.h"

namespace dlo {
namespace {

/// A reference frame whose heights follow f(x, y) exactly at every cell centre.
template <typename F>
HeightFrame referenceOf(F f) {
  const GridGeometry geo = GridGeometry::centred(400, 400, 0.1);
  std::vector<float> h(geo.cellCount());
  std::vector<std::uint32_t> n(geo.cellCount(), 5u);
  for (int r = 0; r < geo.rows; ++r)
    for (int c = 0; c < geo.cols; ++c)
      h[r * geo.cols + c] = static_cast<float>(f(geo.cellCentreX(c), geo.cellCentreY(r)));
  return HeightFrame::fromGrid(HeightGrid::fromCells(geo, h, n, 3), 1, SelectionParams(), false);
}

/// e(exp(xi) T) by central differences, in double precision.
template <int N>
Eigen::Matrix<double, N, 1> numericalJacobian(const HeightSampler& s, const SelectedCell& cell,
                                              const Eigen::Isometry3d& T) {
  const int index3[3] = {0, 1, 5};
  // The sampler works in float: a step large enough that rounding stays below 0.1 %.
  constexpr double h = 1e-3;
  Eigen::Matrix<double, N, 1> J;
  for (int k = 0; k < N; ++k) {
    Vector6d d = Vector6d::Zero();
    d(N == 6 ? k : index3[k]) = h;
    double e[2];
    for (int side = 0; side < 2; ++side) {
      const Eigen::Isometry3d Tk = expSE3(side == 0 ? d : Vector6d(-d)) * T;
      Eigen::Matrix<double, N, 1> unused;
      const Eigen::Matrix3d R = Tk.linear();
      const Eigen::Vector3d t = Tk.translation();
      EXPECT_TRUE(heightResidual<N>(s, cell, R, t, e[side], unused));
    }
    J(k) = (e[0] - e[1]) / (2 * h);
  }
  return J;
}

template <int N>
void expectJacobiansMatch(const HeightFrame& ref, double tolerance, unsigned seed) {
  const HeightSampler& s = ref.levels()[0].sampler;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-12.0, 12.0), height(-2.0, 3.0), ang(-0.3, 0.3);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Isometry3d T = poseFromXYZYPR(pos(rng) * 0.2, pos(rng) * 0.2, ang(rng),
                                               ang(rng) * 3, ang(rng) * 0.3, ang(rng) * 0.3);
    const SelectedCell cell{static_cast<float>(pos(rng)), static_cast<float>(pos(rng)),
                            static_cast<float>(height(rng))};
    double e = 0.0;
    Eigen::Matrix<double, N, 1> J;
    const Eigen::Matrix3d R = T.linear();
    const Eigen::Vector3d t = T.translation();
    ASSERT_TRUE(heightResidual<N>(s, cell, R, t, e, J));
    const Eigen::Matrix<double, N, 1> Jn = numericalJacobian<N>(s, cell, T);
    EXPECT_LT((J - Jn).norm(), tolerance * (1.0 + Jn.norm()))
        << "trial " << trial << "\nanalytic  " << J.transpose() << "\nnumerical " << Jn.transpose();
  }
}

// On a tilted plane, bilinear interpolation and central differences are exact, so the analytic
// and numerical Jacobians must agree to rounding.
TEST(HeightResidualJacobian, MatchesNumericalDifferentiationIn3DofOnAPlane) {
  expectJacobiansMatch<3>(referenceOf([](double x, double y) { return 0.2 * x - 0.35 * y + 0.5; }),
                          2e-3, 1);
}

TEST(HeightResidualJacobian, MatchesNumericalDifferentiationIn6DofOnAPlane) {
  expectJacobiansMatch<6>(referenceOf([](double x, double y) { return 0.2 * x - 0.35 * y + 0.5; }),
                          2e-3, 2);
}

// On a smooth curved surface the sampled gradient approximates the derivative of the
// interpolant to O(res^2): agreement within a couple of percent.
TEST(HeightResidualJacobian, MatchesNumericalDifferentiationIn6DofOnACurvedSurface) {
  expectJacobiansMatch<6>(referenceOf([](double x, double y) {
                            return 0.8 * std::sin(0.25 * x) + 0.5 * std::cos(0.2 * y) +
                                   0.01 * x * y;
                          }),
                          3e-2, 3);
}

TEST(HeightResidualJacobian, RotationColumnsAreNotThePinholeOnes) {
  // Guard against the paper's equation 17: for a pure yaw about the origin, a cell at (x, y)
  // moves by (-y, x) dtheta, whatever its height; no division by depth or height appears.
  const HeightFrame ref = referenceOf([](double x, double) { return 0.5 * x; });
  const SelectedCell cell{4.0f, 3.0f, 10.0f};
  double e = 0.0;
  Eigen::Matrix<double, 3, 1> J;
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d t = Eigen::Vector3d::Zero();
  ASSERT_TRUE(heightResidual<3>(ref.levels()[0].sampler, cell, R, t, e, J));
  EXPECT_NEAR(J(0), 0.5, 1e-5);
  EXPECT_NEAR(J(1), 0.0, 1e-5);
  EXPECT_NEAR(J(2), -0.5 * 3.0, 1e-4);
}

TEST(RigidTransform, YawPitchRollRoundTripsThroughPoseFromXYZYPR) {
  const Eigen::Isometry3d T = poseFromXYZYPR(1, 2, 3, 0.3, -0.2, 0.1);
  const Eigen::Vector3d ypr = yawPitchRoll(T.linear());
  EXPECT_NEAR(ypr(0), 0.3, 1e-12);
  EXPECT_NEAR(ypr(1), -0.2, 1e-12);
  EXPECT_NEAR(ypr(2), 0.1, 1e-12);
}

TEST(RigidTransform, ExpOfAPureRotationIsThatRotation) {
  Vector6d xi = Vector6d::Zero();
  xi(5) = 0.4;
  const Eigen::Isometry3d T = expSE3(xi);
  EXPECT_NEAR(yawPitchRoll(T.linear())(0), 0.4, 1e-12);
  EXPECT_NEAR(T.translation().norm(), 0.0, 1e-12);
}

TEST(RigidTransform, LogInvertsExpForRotationsFromTinyToLarge) {
  // A 2 m step with rotations down to 1e-9 rad, as planar poses produce: the closed form of
  // V^-1 cancelled catastrophically there (a 1.94 m step came out as 2.56 m).
  for (const double angle :
       {0.0, 1e-12, 1e-9, 3e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 2e-3, 0.1, 1.0, 2.5}) {
    SCOPED_TRACE("angle " + std::to_string(angle));
    Vector6d xi;
    xi << 1.9, 0.3, -0.1, 0.2 * angle, -0.3 * angle, angle;
    const Vector6d back = logSE3(expSE3(xi));
    EXPECT_LT((back - xi).norm(), 1e-9);
  }
}

TEST(RigidTransform, CovarianceOfYawMapsToYawAtIdentity) {
  Matrix6d cov = Matrix6d::Zero();
  cov(5, 5) = 0.01;  // wz
  cov(0, 0) = 0.04;  // x
  const Matrix6d out = twistCovarianceToXYZYPR(Eigen::Isometry3d::Identity(), cov);
  EXPECT_NEAR(out(3, 3), 0.01, 1e-8);  // yaw
  EXPECT_NEAR(out(0, 0), 0.04, 1e-8);
  EXPECT_NEAR(out(5, 5), 0.0, 1e-8);  // roll
}

}  // namespace
}  // namespace dlo
