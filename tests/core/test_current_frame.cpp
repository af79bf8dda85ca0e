// A scan built only to be registered (FrameUse::kCurrentOnly, deskewed while rasterised) must
// select exactly the cells a full frame of the deskewed scan selects: the shortcuts (no copy of
// the cloud, no hole filling of the finest level, gradients of measured cells only) are exact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "../test_data.h"
#include "dlo/core/deskew.h"
#include "dlo/core/direct_aligner.h"
#include "dlo/core/dlo_params.h"
#include "dlo/core/height_frame.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/formats/kitti_bin.h"

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

// The batched rasterisation (four points at a time, one pose per run of points in the same
// time bin) against the deskewed copy on the cases it treats apart: times out of order (runs of
// one point), a count that leaves a tail of one to three points, and points that must be
// skipped (NaN, infinite, outside the grid or the height band) in every position of a batch.
TEST(SweepRasterisation, ShuffledTimesAndBadPointsGiveTheSameCellsAsTheDeskewedCloud) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> xy(-25.0f, 25.0f), z(-12.0f, 12.0f), t(-0.1f, 0.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const size_t n : {size_t{0}, size_t{1}, size_t{3}, size_t{4}, size_t{5003}, size_t{20001}}) {
    PointCloud points(n);
    std::vector<float> times(n);
    for (size_t i = 0; i < n; ++i) {
      points[i] = Eigen::Vector3f(xy(rng), xy(rng), z(rng));
      if (i % 7 == 3) points[i].x() = nan;
      if (i % 11 == 5) points[i].z() = -inf;
      if (i % 13 == 6) points[i].y() = inf;
      times[i] = t(rng);
    }
    Vector6d velocity;
    velocity << 12.0, -1.0, 0.2, 0.01, -0.02, 0.5;
    const SweepMotion motion(times, velocity);
    const GridGeometry geo = GridGeometry::centred(200, 160, 0.25);
    HeightGrid fused;
    fused.rasterise(points, motion, geo, 1, -10.0, 10.0);
    const HeightGrid copied = HeightGrid::fromPoints(deskew(points, motion), geo, 1, -10.0, 10.0);
    EXPECT_EQ(fused.validCellCount(), copied.validCellCount()) << n << " points";
    EXPECT_EQ(fused.heights(), copied.heights()) << n << " points";
    EXPECT_EQ(fused.validMask(), copied.validMask()) << n << " points";
    if (n > 1000) {
      EXPECT_GT(fused.validCellCount(), static_cast<int>(n / 10)) << n << " points";
    }
  }
}

// Weighted points (batched four at a time, like sweeps) count n times: the same cells as the
// raw cloud with each point repeated n times, seen from a pose, bad points skipped anywhere.
TEST(SweepRasterisation, WeightedPointsCountAsManyRawPointsFromAnyPose) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> xy(-25.0f, 25.0f), z(-12.0f, 12.0f);
  std::uniform_int_distribution<int> weight(0, 4);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() << 1.5, -2.0, 0.25;
  const Eigen::Isometry3f posef = pose.cast<float>();
  for (const size_t n : {size_t{1}, size_t{6}, size_t{4099}}) {
    WeightedCloud weighted(n);
    PointCloud repeated;
    for (size_t i = 0; i < n; ++i) {
      weighted[i] = WeightedPoint{Eigen::Vector3f(xy(rng), xy(rng), z(rng)),
                                  static_cast<std::uint32_t>(weight(rng))};
      if (i % 9 == 4) weighted[i].p.y() = nan;
      for (std::uint32_t k = 0; k < weighted[i].n; ++k) repeated.push_back(posef * weighted[i].p);
    }
    const GridGeometry geo = GridGeometry::centred(100, 90, 0.5);
    HeightGrid a;
    a.rasterise(weighted, pose, geo, 2, -10.0, 10.0);
    const HeightGrid b = HeightGrid::fromPoints(repeated, geo, 2, -10.0, 10.0);
    ASSERT_EQ(a.validMask(), b.validMask()) << n << " points";
    for (int r = 0; r < geo.rows; ++r) {
      for (int c = 0; c < geo.cols; ++c) {
        EXPECT_EQ(a.count(r, c), b.count(r, c));
        if (a.isValid(r, c)) {
          EXPECT_NEAR(a.height(r, c), b.height(r, c), 1e-4f);
        }
      }
    }
    if (n > 1000) {
      EXPECT_GT(a.validCellCount(), 300);
    }
  }
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

TEST_F(CurrentOnlyFrame, MovingARangeOfPointsEqualsMovingEach) {
  // SweepMotion::apply over a range finds the bins of a batch together; from a point in the
  // middle of the sweep and across several batches, each point must be moved as apply(i, p).
  const SweepMotion motion(*times_, velocity_);
  const size_t first = 1001, n = 700;
  ASSERT_GT(scan_->size(), first + n);
  std::vector<Eigen::Vector3f> out(n);
  motion.apply(first, scan_->data() + first, n, out.data());
  for (size_t k = 0; k < n; ++k) {
    const Eigen::Vector3f each = motion.apply(first + k, (*scan_)[first + k]);
    ASSERT_EQ(std::memcmp(out[k].data(), each.data(), sizeof(float) * 3), 0) << "point " << k;
  }
}

TEST(SweepMotion, BinsOfManyTimesEqualTheBinOfEach) {
  // Random times, the range's ends, halfway cases and a NaN; an odd count for the scalar tail.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> time(-0.05f, 0.05f);
  std::vector<float> times(1003);
  for (float& t : times) t = time(rng);
  times[10] = -0.05f;
  times[11] = 0.05f;
  times[12] = std::numeric_limits<float>::quiet_NaN();
  times[13] = 0.0f;
  Vector6d velocity;
  velocity << 10.0, 0.0, 0.0, 0.0, 0.0, 0.3;
  for (int bins : {1, 7, 128}) {
    const SweepMotion motion(times, velocity, bins);
    std::vector<int> out(times.size(), -1);
    motion.bins(times.data(), times.size(), out.data());
    for (size_t i = 0; i < times.size(); ++i) {
      ASSERT_EQ(out[i], motion.bin(times[i])) << "time " << times[i] << ", bins " << bins;
      ASSERT_GE(out[i], 0);
      ASSERT_LE(out[i], bins);
    }
    EXPECT_EQ(out[10], 0);
    EXPECT_EQ(out[11], bins);
    EXPECT_EQ(out[12], 0);  // a NaN time takes the first pose
  }
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
  std::vector<float> height(raw.cols()), has(raw.cols()), scratch;
  for (int r = 0; r < raw.rows(); ++r) {
    raw.pulledRow(r, &source, height.data(), has.data(), scratch);
    for (int c = 0; c < raw.cols(); ++c) {
      ASSERT_EQ(has[c] != 0.0f, filled.hasSupport(r, c)) << r << ", " << c;
      if (has[c] == 0.0f) continue;
      ASSERT_EQ(height[c], filled.height(r, c)) << r << ", " << c;
      pulled += raw.isValid(r, c) ? 0 : 1;
    }
    // A range of columns gives the same values as the whole row (odd bounds on purpose).
    std::vector<float> part_height(raw.cols(), -7.0f), part_has(raw.cols(), -7.0f);
    raw.pulledRow(r, &source, part_height.data(), part_has.data(), scratch, 37, 251);
    for (int c = 0; c < raw.cols(); ++c) {
      if (c < 37 || c >= 251) {
        ASSERT_EQ(part_height[c], -7.0f) << "column " << c << " outside the range was written";
        continue;
      }
      ASSERT_EQ(part_has[c], has[c]) << r << ", " << c;
      if (has[c] != 0.0f) {
        ASSERT_EQ(part_height[c], height[c]) << r << ", " << c;
      }
    }
    // Without a source, a row has the grid's own heights only.
    raw.pulledRow(r, nullptr, height.data(), has.data(), scratch);
    for (int c = 0; c < raw.cols(); ++c) {
      ASSERT_EQ(has[c] != 0.0f, raw.hasSupport(r, c)) << r << ", " << c;
      if (has[c] != 0.0f) {
        ASSERT_EQ(height[c], raw.height(r, c)) << r << ", " << c;
      }
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

TEST_F(CurrentOnlyFrame, SelectsTheSameCellsInAGridOfMoreThan1024Columns) {
  // Wide grids take wider chunks of columns in the current-only selection: the columns past
  // 1024 must still be selected like a full frame selects them.
  DloParams p;
  p.grid.cols = 1500;
  p.grid.rows = 200;
  p.grid.resolution = 0.1;
  const SweepMotion motion(*times_, velocity_);
  HeightFrame current;
  current.build(*scan_, motion, p.grid, p.selection, false, FrameUse::kCurrentOnly);
  const HeightFrame full =
      HeightFrame::fromPoints(deskew(*scan_, motion), p.grid, p.selection, false);
  const std::vector<SelectedCell>& a = current.levels().front().cells;
  const std::vector<SelectedCell>& b = full.levels().front().cells;
  ASSERT_EQ(a.size(), b.size());
  const float far_x = static_cast<float>(-0.5 * p.grid.cols * p.grid.resolution + 102.4);
  int beyond = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
    EXPECT_EQ(a[i].h, b[i].h);
    beyond += a[i].x > far_x ? 1 : 0;
  }
  EXPECT_GT(beyond, 10);  // cells in columns past 1024
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
