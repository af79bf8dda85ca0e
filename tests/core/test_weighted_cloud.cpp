// Voxelisation, which keyframe clouds, the long-term map and the classic baselines' filters
// rest on: voxel order, centroids and counts, floor (not truncation) below zero, bad points and
// empty weights, weights adding up, VoxelMerger against voxelise() bit for bit, huge coordinates.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "../test_data.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/mrpt/scan_file.h"

namespace dlo {
namespace {

/// Same voxels in the same order, centroids equal to the bit.
void expectIdentical(const WeightedCloud& a, const WeightedCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE("voxel " + std::to_string(i));
    ASSERT_EQ(a[i].n, b[i].n);
    ASSERT_EQ(std::memcmp(a[i].p.data(), b[i].p.data(), sizeof(float) * 3), 0)
        << a[i].p.transpose() << " vs " << b[i].p.transpose();
  }
}

TEST(Voxelise, VoxelsComeInTheOrderOfTheirFirstPointWithCentroidsAndCounts) {
  // Voxels of 1 m: (2, 0, 0) first, then (-1, 0, 0) (floor, not truncation), then (0, 0, 0).
  const PointCloud points = {{2.5f, 0.5f, 0.5f},  {-0.5f, 0.5f, 0.5f},  {0.25f, 0.5f, 0.5f},
                             {2.75f, 0.5f, 0.5f}, {-0.25f, 0.5f, 0.5f}, {0.0f, 0.5f, 0.5f}};
  const WeightedCloud v = voxelise(points, 1.0);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_FLOAT_EQ(v[0].p.x(), 2.625f);
  EXPECT_EQ(v[0].n, 2u);
  EXPECT_FLOAT_EQ(v[1].p.x(), -0.375f);
  EXPECT_EQ(v[1].n, 2u);
  EXPECT_FLOAT_EQ(v[2].p.x(), 0.125f);
  EXPECT_EQ(v[2].n, 2u);
}

TEST(Voxelise, NonFinitePointsAndEmptyWeightsAreSkipped) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const PointCloud points = {{nan, 0, 0}, {1, 1, 1}, {0, inf, 0}, {1.01f, 1, 1}, {0, 0, -inf}};
  const WeightedCloud v = voxelise(points, 0.1);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].n, 2u);

  WeightedCloud weighted = unitWeights(points);
  weighted[1].n = 0;  // an empty voxel counts for nothing
  const WeightedCloud w = voxelise(weighted, 0.1);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].n, 1u);
  EXPECT_FLOAT_EQ(w[0].p.x(), 1.01f);

  EXPECT_TRUE(voxelise(PointCloud{}, 0.1).empty());
  EXPECT_TRUE(voxelise(PointCloud{{nan, nan, nan}}, 0.1).empty());
}

TEST(Voxelise, ARealSweepKeepsEveryPointAndMergerAgreesBitForBit) {
  const PointCloud scan = loadKittiBin(test::sharedData("kitti_00_000000.bin.gz"));
  const WeightedCloud fine = voxelise(scan, 0.05);
  EXPECT_EQ(pointCount(fine), scan.size());
  EXPECT_LT(fine.size(), scan.size());
  // Re-voxelising adds the weights: the same counts as voxelising the points at once.
  const WeightedCloud coarse = voxelise(fine, 0.5);
  EXPECT_EQ(pointCount(coarse), scan.size());
  EXPECT_EQ(coarse.size(), voxelise(scan, 0.5).size());
  // The merger, fed in two halves, is voxelise() of the whole.
  VoxelMerger merger(0.05);
  const WeightedCloud all = unitWeights(scan);
  merger.add(WeightedCloud(all.begin(), all.begin() + all.size() / 2));
  merger.add(WeightedCloud(all.begin() + all.size() / 2, all.end()));
  expectIdentical(merger.result(), fine);
}

TEST(Voxelise, CoordinatesBeyondTheKeyRangeShareTheEdgeVoxel) {
  // 21 bits per axis: +-1,048,576 voxels. At 0.01 m that is +-10.5 km; points beyond it are
  // clamped into the edge voxels instead of wrapping around onto other voxels.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> far(20000.0f, 30000.0f);
  PointCloud points;
  for (int i = 0; i < 100; ++i) points.emplace_back(far(rng), 0.005f, 0.005f);
  points.emplace_back(0.005f, 0.005f, 0.005f);
  const WeightedCloud v = voxelise(points, 0.01);
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].n, 100u);
  EXPECT_GT(v[0].p.x(), 20000.0f);
  EXPECT_EQ(v[1].n, 1u);
}

}  // namespace
}  // namespace dlo
