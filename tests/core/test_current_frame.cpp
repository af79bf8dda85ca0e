// A scan built only to be registered (FrameUse::kCurrentOnly, deskewed while rasterised) must
// select exactly the cells a full frame of the deskewed scan selects: the shortcuts (no copy of
// the cloud, no hole filling of the finest level, gradients of measured cells only) are exact.
#include <gtest/gtest.h>

#include <cmath>

#include "../test_data.h"
#include "dlo/core/deskew.h"
#include "dlo/core/direct_aligner.h"
#include "dlo/core/dlo_params.h"
#include "dlo/core/height_frame.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/mrpt/scan_file.h"

namespace dlo {
namespace {

class CurrentOnlyFrame : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scan_ = new PointCloud(loadKittiBin(test::sharedData("kitti_00_000000.bin.gz")));
    // A sweep of 0.1 s in firing order, driving at 10 m/s and turning at 20 deg/s.
    times_ = new std::vector<float>(scan_->size());
    for (size_t i = 0; i < scan_->size(); ++i)
      (*times_)[i] = -0.1f + 0.1f * static_cast<float>(i) / static_cast<float>(scan_->size());
    velocity_ << 10.0, 0.0, 0.0, 0.0, 0.0, 20.0 * M_PI / 180.0;
  }
  static void TearDownTestSuite() {
    delete scan_;
    delete times_;
  }
  static PointCloud* scan_;
  static std::vector<float>* times_;
  static Vector6d velocity_;
};
PointCloud* CurrentOnlyFrame::scan_ = nullptr;
std::vector<float>* CurrentOnlyFrame::times_ = nullptr;
Vector6d CurrentOnlyFrame::velocity_;

TEST_F(CurrentOnlyFrame, RasterisingWithTheSweepMotionEqualsRasterisingTheDeskewedCloud) {
  const DloParams p;
  const GridGeometry geo = GridGeometry::centred(p.grid.cols, p.grid.rows, p.grid.resolution);
  const SweepMotion motion(*times_, velocity_);
  HeightGrid fused;
  fused.rasterise(*scan_, motion, geo, p.grid.min_points, p.grid.min_z, p.grid.max_z);
  const HeightGrid copied = HeightGrid::fromPoints(deskew(*scan_, motion), geo, p.grid.min_points,
                                                   p.grid.min_z, p.grid.max_z);
  ASSERT_GT(fused.validCellCount(), 1000);
  EXPECT_EQ(fused.validCellCount(), copied.validCellCount());
  EXPECT_EQ(fused.heights(), copied.heights());
  EXPECT_EQ(fused.validMask(), copied.validMask());
}

TEST_F(CurrentOnlyFrame, DeskewMovesPointsByTheMotionOfTheirTime) {
  const SweepMotion motion(*times_, velocity_);
  const PointCloud out = deskew(*scan_, *times_, velocity_);
  ASSERT_EQ(out.size(), scan_->size());
  // The first point was measured 0.1 s before the reference: about 1 m behind, turned by 2 deg.
  const Eigen::Vector3f expected = expSE3(velocity_ * (*times_)[0]).cast<float>() * (*scan_)[0];
  EXPECT_LT((out[0] - expected).norm(), 1e-4f);
  EXPECT_LT((motion.apply(0, (*scan_)[0]) - expected).norm(), 1e-4f);
  EXPECT_TRUE(SweepMotion().empty());
  EXPECT_FALSE(SweepMotion(*times_, velocity_).fits(scan_->size() + 1));
}

TEST_F(CurrentOnlyFrame, PulledHeightsEqualTheFilledGrid) {
  const DloParams p;
  const GridGeometry geo = GridGeometry::centred(p.grid.cols, p.grid.rows, p.grid.resolution);
  const HeightGrid raw =
      HeightGrid::fromPoints(*scan_, geo, p.grid.min_points, p.grid.min_z, p.grid.max_z);
  HeightGrid coarse = raw.coarser();
  coarse.fillHolesFrom(coarse.coarser());
  HeightGrid filled = raw;
  filled.fillHolesFrom(coarse);
  PullSource source;
  coarse.preparePull(source);
  int pulled = 0;
  for (int r = 0; r < raw.rows(); ++r) {
    for (int c = 0; c < raw.cols(); ++c) {
      float h = 0.0f;
      const bool ok = raw.pulledHeight(r, c, source, h);
      ASSERT_EQ(ok, filled.hasSupport(r, c)) << r << ", " << c;
      if (!ok) continue;
      ASSERT_FLOAT_EQ(h, filled.height(r, c)) << r << ", " << c;
      pulled += raw.isValid(r, c) ? 0 : 1;
    }
  }
  EXPECT_GT(pulled, 10000);
}

TEST_F(CurrentOnlyFrame, SelectsTheSameCellsAsAFullFrameOfTheDeskewedScan) {
  for (int dof : {3, 6}) {
    DloParams p;
    p.solver.dof = dof;
    const SweepMotion motion(*times_, velocity_);
    HeightFrame current;
    current.build(*scan_, motion, p.grid, p.selection, p.includeGround(), FrameUse::kCurrentOnly);
    const HeightFrame full =
        HeightFrame::fromPoints(deskew(*scan_, motion), p.grid, p.selection, p.includeGround());
    EXPECT_FALSE(current.canBeReference());
    EXPECT_TRUE(full.canBeReference());
    ASSERT_EQ(current.levels().size(), full.levels().size());
    for (size_t k = 0; k < full.levels().size(); ++k) {
      const std::vector<SelectedCell>& a = current.levels()[k].cells;
      const std::vector<SelectedCell>& b = full.levels()[k].cells;
      ASSERT_EQ(a.size(), b.size()) << "dof " << dof << ", level " << k;
      ASSERT_GT(a.size(), 50u);
      for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].x, b[i].x);
        EXPECT_EQ(a[i].y, b[i].y);
        EXPECT_EQ(a[i].h, b[i].h);
        EXPECT_EQ(a[i].ground, b[i].ground);
      }
    }
  }
}

TEST_F(CurrentOnlyFrame, CannotServeAsAReference) {
  const DloParams p;
  HeightFrame current;
  current.build(*scan_, SweepMotion(), p.grid, p.selection, false, FrameUse::kCurrentOnly);
  const HeightFrame full = HeightFrame::fromPoints(*scan_, p.grid, p.selection, false);
  const DirectAligner aligner(p.solver);
  EXPECT_THROW(aligner.align(current, full, Eigen::Isometry3d::Identity()), std::invalid_argument);
  EXPECT_NO_THROW(aligner.align(full, current, Eigen::Isometry3d::Identity()));
}

TEST_F(CurrentOnlyFrame, AReferenceOnlyFrameRegistersLikeAFullOneAndCannotBeCurrent) {
  const DloParams p;
  const WeightedCloud cloud = voxelise(*scan_, 0.05);
  const std::vector<PosedCloud> parts{PosedCloud{&cloud, Eigen::Isometry3d::Identity()}};
  HeightFrame reference;
  reference.build(parts, p.grid, p.selection, false, FrameUse::kReferenceOnly);
  HeightFrame full;
  full.build(parts, p.grid, p.selection, false);
  EXPECT_TRUE(reference.canBeReference());
  EXPECT_FALSE(reference.canBeCurrent());
  for (const FrameLevel& level : reference.levels()) EXPECT_TRUE(level.cells.empty());

  HeightFrame current;
  current.build(*scan_, SweepMotion(), p.grid, p.selection, false, FrameUse::kCurrentOnly);
  Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  guess.translation() << 0.3, -0.2, 0.0;
  const DirectAligner aligner(p.solver);
  const AlignmentResult a = aligner.align(reference, current, guess);
  const AlignmentResult b = aligner.align(full, current, guess);
  EXPECT_TRUE(a.pose.isApprox(b.pose, 0.0));  // the same samplers, bit for bit
  EXPECT_EQ(a.cells, b.cells);
  EXPECT_THROW(aligner.align(full, reference, guess), std::invalid_argument);
}

}  // namespace
}  // namespace dlo
