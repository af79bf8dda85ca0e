// Recovery of known motions on the real HDL-64 scan of ../shared/data.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../test_data.h"
#include "dlo/core/direct_aligner.h"
#include "dlo/core/dlo_params.h"
#include "dlo/core/height_frame.h"
#include "dlo/core/units.h"
#include "dlo/formats/kitti_bin.h"

namespace dlo {
namespace {

struct Motion {
  double x, y, z, yaw_deg, pitch_deg, roll_deg;
};

class RealScanRegistration : public ::testing::TestWithParam<Motion> {
 protected:
  static void SetUpTestSuite() {
    const PointCloud scan = loadKittiBin(test::sharedData("kitti_00_000000.bin.gz"));
    test::splitEvenOdd(scan, *even_, *odd_);
  }
  static PointCloud* even_;
  static PointCloud* odd_;

  void recover(int dof) {
    const Motion m = GetParam();
    DloParams params;
    params.solver.dof = dof;
    const double z = dof == 6 ? m.z : 0.0;
    const double pitch = dof == 6 ? m.pitch_deg * kDeg : 0.0;
    const double roll = dof == 6 ? m.roll_deg * kDeg : 0.0;
    const Eigen::Isometry3d truth = poseFromXYZYPR(m.x, m.y, z, m.yaw_deg * kDeg, pitch, roll);
    const HeightFrame ref =
        HeightFrame::fromPoints(*even_, params.grid, params.selection, params.includeGround());
    const HeightFrame cur = HeightFrame::fromPoints(test::expressIn(*odd_, truth), params.grid,
                                                    params.selection, params.includeGround());
    const AlignmentResult r =
        DirectAligner(params.solver).align(ref, cur, Eigen::Isometry3d::Identity());
    const Eigen::Isometry3d err = truth.inverse() * r.pose;
    const double dt = err.translation().norm();
    const double dr = Eigen::AngleAxisd(err.linear()).angle() / kDeg;
    std::printf(
        "ratio %.2e dof %d motion (%.2f %.2f %.2f | %.1f %.1f %.1f): err %.4f m %.4f deg, it %d, "
        "cells %d, rms %.4f, solve %.2f ms\n",
        r.information_ratio, dof, m.x, m.y, z, m.yaw_deg, pitch / kDeg, roll / kDeg, dt, dr,
        r.iterations, r.cells, r.rms_height_error, r.times.solve_ms);
    EXPECT_LT(dt, 0.03);
    EXPECT_LT(dr, 0.1);
    EXPECT_FALSE(r.degenerate);
  }
};
PointCloud* RealScanRegistration::even_ = new PointCloud;
PointCloud* RealScanRegistration::odd_ = new PointCloud;

TEST_P(RealScanRegistration, RecoversKnownMotionIn3Dof) {
  recover(3);
}
TEST_P(RealScanRegistration, RecoversKnownMotionIn6Dof) {
  recover(6);
}

INSTANTIATE_TEST_SUITE_P(UpTo2mAnd10deg, RealScanRegistration,
                         ::testing::Values(Motion{0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
                                           Motion{0.5, -0.3, 0.05, 2.0, 0.5, -0.5},
                                           Motion{1.2, 0.8, -0.10, -5.0, 1.0, 1.5},
                                           Motion{2.0, 0.0, 0.10, 10.0, -1.5, 1.0},
                                           Motion{-1.4, 1.4, 0.20, -10.0, 2.0, -2.0}));

}  // namespace
}  // namespace dlo

namespace dlo {
namespace {

/// Points on the plane z = -1.7 (with 1 cm noise) beyond the 40 m window, plus optional walls
/// parallel to x at y = +-4 m (a corridor), sampled like a LiDAR does: along horizontal lines,
/// one per laser ring.
PointCloud syntheticScene(unsigned seed, bool corridor) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> xy(-30.0f, 30.0f);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  PointCloud pts;
  for (int i = 0; i < 560000; ++i) pts.emplace_back(xy(rng), xy(rng), -1.7f + noise(rng));
  if (corridor) {
    // Like a LiDAR sees a wall: horizontal lines, one per ring, evenly along the wall, so every
    // cell of a wall holds the same mix of heights and nothing varies along x.
    // Longer than both 40 m windows: a wall end inside one would be real x information.
    constexpr int kRings = 16, kPerWall = 600 * 8 * kRings;
    for (int wall = 0; wall < 2; ++wall) {
      for (int i = 0; i < kPerWall; ++i) {
        const float x = -30.0f + 60.0f * (static_cast<float>(i) + 0.5f) / kPerWall;
        const float y = (wall == 0 ? 4.0f : -4.0f) + noise(rng);
        pts.emplace_back(x, y, -1.6f + 0.2f * static_cast<float>(i % kRings));
      }
    }
  }
  return pts;
}

AlignmentResult alignSynthetic(int dof, bool corridor, const Eigen::Isometry3d& truth,
                               double degeneracy_ratio = SolverParams().degeneracy_eigen_ratio) {
  DloParams params;
  params.solver.dof = dof;
  params.solver.degeneracy_eigen_ratio = degeneracy_ratio;
  const HeightFrame ref = HeightFrame::fromPoints(syntheticScene(1, corridor), params.grid,
                                                  params.selection, params.includeGround());
  const HeightFrame cur =
      HeightFrame::fromPoints(test::expressIn(syntheticScene(2, corridor), truth), params.grid,
                              params.selection, params.includeGround());
  return DirectAligner(params.solver).align(ref, cur, Eigen::Isometry3d::Identity());
}

TEST(DegenerateScene, AFeaturelessPlaneIsReportedAndThePriorKeptIn3Dof) {
  const AlignmentResult r = alignSynthetic(3, false, poseFromXYZYPR(0.5, 0.3, 0, 0.05, 0, 0));
  EXPECT_TRUE(r.degenerate);
  // No confident wrong answer: the pose stays at the initial guess, with a huge variance.
  EXPECT_LT(r.pose.translation().norm(), 1e-6);
  EXPECT_GT(r.covariance(0, 0), 1e3);
  EXPECT_GT(r.covariance(5, 5), 1e3);
}

TEST(DegenerateScene, AFeaturelessPlaneStillGivesZRollPitchIn6Dof) {
  const Eigen::Isometry3d truth = poseFromXYZYPR(0.5, 0.3, 0.12, 0.05, 0.02, -0.015);
  const AlignmentResult r = alignSynthetic(6, false, truth);
  EXPECT_TRUE(r.degenerate);
  const Eigen::Vector3d ypr = yawPitchRoll(r.pose.linear());
  EXPECT_NEAR(r.pose.translation().z(), 0.12, 0.01);
  EXPECT_NEAR(ypr(1), 0.02, 0.002);
  EXPECT_NEAR(ypr(2), -0.015, 0.002);
  // x, y and yaw are unobservable on a plane: they keep the prior instead of drifting.
  EXPECT_LT(r.pose.translation().head<2>().norm(), 0.02);
  EXPECT_LT(std::abs(ypr(0)), 0.002);
}

TEST(DegenerateScene, ACorridorKeepsThePriorAlongItsAxisButFixesTheRest) {
  // At 0.1 m, hole-filled ground next to the walls leaves a little spurious x information (ratio
  // about 0.06, above the default threshold); the 0.2 m level has none, and judges.
  const AlignmentResult r = alignSynthetic(3, true, poseFromXYZYPR(0.6, 0.25, 0, 0.03, 0, 0));
  EXPECT_TRUE(r.degenerate);
  EXPECT_LT(r.information_ratio, SolverParams().degeneracy_eigen_ratio);
  EXPECT_NEAR(r.pose.translation().y(), 0.25, 0.03);
  EXPECT_NEAR(yawPitchRoll(r.pose.linear())(0), 0.03, 0.005);
  EXPECT_LT(std::abs(r.pose.translation().x()), 0.05);  // along the corridor: the prior (0)
  EXPECT_GT(r.covariance(0, 0), 1e3);
}

TEST(RealScanRegistration, AnEmptyCurrentScanIsDegenerateAndKeepsTheGuess) {
  DloParams params;
  const HeightFrame ref =
      HeightFrame::fromPoints(loadKittiBin(test::sharedData("kitti_00_000000.bin.gz")), params.grid,
                              params.selection, false);
  const HeightFrame cur = HeightFrame::fromPoints({}, params.grid, params.selection, false);
  EXPECT_TRUE(cur.empty());
  const Eigen::Isometry3d guess = poseFromXYZYPR(1.0, 0.0, 0.0, 0.1, 0.0, 0.0);
  const AlignmentResult r = DirectAligner(params.solver).align(ref, cur, guess);
  EXPECT_TRUE(r.degenerate);
  EXPECT_EQ(r.cells, 0);
  EXPECT_TRUE(r.pose.isApprox(guess, 1e-9));
}

TEST(RealScanRegistration, AScanOfAFewCellsIsDegenerateAndKeepsTheGuess) {
  // A few cells are enough for Gauss-Newton to move (it needs 9 residuals in 3-DoF) but not to
  // be believed: the result is the initial guess, flagged, not a confident wrong answer.
  DloParams params;
  const PointCloud scan = loadKittiBin(test::sharedData("kitti_00_000000.bin.gz"));
  PointCloud patch;  // 3 m x 3 m around (12, -5): 459 points, 19 selected cells
  for (const Eigen::Vector3f& p : scan) {
    if (std::abs(p.x() - 12.0f) < 1.5f && std::abs(p.y() + 5.0f) < 1.5f) patch.push_back(p);
  }
  const HeightFrame ref = HeightFrame::fromPoints(scan, params.grid, params.selection, false);
  const HeightFrame cur = HeightFrame::fromPoints(patch, params.grid, params.selection, false);
  const Eigen::Isometry3d guess = poseFromXYZYPR(0.3, -0.2, 0.0, 0.02, 0.0, 0.0);
  const AlignmentResult r = DirectAligner(params.solver).align(ref, cur, guess);
  EXPECT_TRUE(r.degenerate);
  EXPECT_GT(r.iterations, 0);
  EXPECT_LT(r.cells, params.solver.min_cells);
  EXPECT_TRUE(r.pose.isApprox(guess, 1e-9));
  EXPECT_GT(r.covariance(0, 0), 1e3);
}

}  // namespace
}  // namespace dlo
