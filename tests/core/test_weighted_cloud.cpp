// Voxelisation, which keyframe clouds, the long-term map and the classic baselines' filters
// rest on: voxel order, centroids and counts, floor (not truncation) below zero, bad points and
// empty weights, weights adding up, VoxelMerger against voxelise() bit for bit, huge coordinates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "../test_data.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/formats/kitti_bin.h"

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

TEST(Voxelise, EveryPointGoesToTheVoxelOfTheFloorOfItsCoordinates) {
  // Keys are computed four points at a time; this checks each point's voxel against the formula
  // written out (floor of the coordinate in voxels, clamped to 21 bits): random points on both
  // sides of zero, points on voxel faces (where truncation and floor differ below zero), and
  // points beyond the key range on both sides, at every position of a batch.
  const double voxel = 0.1;
  const float inv = static_cast<float>(1.0 / voxel);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f);
  std::uniform_int_distribution<int> face(-30, 30);
  PointCloud points;
  for (int i = 0; i < 2000; ++i) {
    switch (i % 4) {
      case 0:
        points.emplace_back(coordinate(rng), coordinate(rng), coordinate(rng));
        break;
      case 1:  // on faces
        points.emplace_back(face(rng) * 0.1f, face(rng) * 0.1f, face(rng) * 0.1f);
        break;
      case 2:  // beyond the key range (+-104.8 km at 0.1 m)
        points.emplace_back(i % 8 == 2 ? -2.0e5f : 3.0e5f, coordinate(rng), -1.0e15f);
        break;
      default:  // a point already seen, so that voxels hold several
        points.push_back(points[static_cast<size_t>(rng() % points.size())]);
    }
  }
  auto axis = [&](float v) {
    const std::int64_t i = static_cast<std::int64_t>(std::floor(v * inv)) + (1 << 20);
    return static_cast<std::uint64_t>(std::clamp<std::int64_t>(i, 0, (1 << 21) - 1));
  };
  std::vector<std::uint64_t> order;
  std::vector<std::pair<Eigen::Vector3f, std::uint32_t>> sums;
  for (const Eigen::Vector3f& p : points) {
    const std::uint64_t key = (axis(p.x()) << 42) | (axis(p.y()) << 21) | axis(p.z());
    const size_t at =
        static_cast<size_t>(std::find(order.begin(), order.end(), key) - order.begin());
    if (at == order.size()) {
      order.push_back(key);
      sums.emplace_back(Eigen::Vector3f::Zero(), 0u);
    }
    sums[at].first += p * 1.0f;
    sums[at].second += 1;
  }
  WeightedCloud expected;
  for (const auto& [sum, n] : sums) expected.push_back({sum / static_cast<float>(n), n});
  expectIdentical(voxelise(points, voxel), expected);
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
