// HeightGrid's vectorised kernels (libs/core/src/simd/height_grid_*.cpp) against their scalar
// references, on fixed-seed random inputs of the kinds rasterisation and hole filling produce.
// Every kernel promises the same result as its reference bit for bit (same operations in the
// same order, no fused multiply-add): the comparisons are exact.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "kernel_test_util.h"
#include "simd/height_grid_kernels.h"

namespace dlo {
namespace {

using test::edgeLengths;
using test::sameBits;

/// A 40 x 30 grid at 0.1 m, off-centre, with a height band of [-1, 2] m.
const GridGeometry kGeometry{-1.7, -1.2, 0.1, 40, 30};
const simd::CellMapping kCells(kGeometry, -1.0, 2.0);

/// A pose like a sweep's motion bin: a small rotation about every axis and a translation.
RowMajorPose somePose(std::mt19937& rng) {
  std::uniform_real_distribution<float> angle(-0.3f, 0.3f), shift(-0.5f, 0.5f);
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.rotate(Eigen::AngleAxisf(angle(rng), Eigen::Vector3f::UnitZ()) *
              Eigen::AngleAxisf(0.1f * angle(rng), Eigen::Vector3f::UnitY()) *
              Eigen::AngleAxisf(0.1f * angle(rng), Eigen::Vector3f::UnitX()));
  pose.translation() = Eigen::Vector3f(shift(rng), shift(rng), 0.2f * shift(rng));
  return RowMajorPose(pose);
}

/// Points over the grid and beyond it on every side, above and below the height band, with a
/// NaN and infinities among them (a sensor's dropouts).
PointCloud somePoints(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> x(-3.0f, 3.0f), y(-2.5f, 2.5f), z(-1.5f, 2.5f);
  PointCloud p(n);
  for (size_t k = 0; k < n; ++k) p[k] = Eigen::Vector3f(x(rng), y(rng), z(rng));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  if (n > 2) p[n / 2] = Eigen::Vector3f(nan, 0.0f, 0.0f);
  if (n > 3) p[n / 3] = Eigen::Vector3f(0.0f, inf, 0.0f);
  if (n > 5) p[n - 2] = Eigen::Vector3f(0.0f, 0.0f, -inf);
  return p;
}

WeightedCloud weighted(const PointCloud& p, std::mt19937& rng) {
  std::uniform_int_distribution<std::uint32_t> count(1, 50);
  WeightedCloud w(p.size());
  for (size_t k = 0; k < p.size(); ++k) w[k] = WeightedPoint{p[k], count(rng)};
  return w;
}

/// Counts how many points fell inside, so that a test sees both kinds.
struct Mapped {
  std::vector<int> idx;
  std::vector<float> z;
  std::vector<std::uint32_t> w;
  std::vector<float> fu, fv;
  /// Where the kernels write the fractions: only with `wanted`.
  simd::CellFractions fractions(bool wanted) {
    return wanted ? simd::CellFractions{fu.data(), fv.data()} : simd::CellFractions{};
  }
  int inside() const {
    int n = 0;
    for (int i : idx) n += i < kCells.discard ? 1 : 0;
    return n;
  }
};

Mapped mapped(size_t n) {
  // Sentinels: a kernel that skips a point leaves them for the comparison to see.
  return Mapped{std::vector<int>(n, -7), std::vector<float>(n, -7.0f),
                std::vector<std::uint32_t>(n, 7u), std::vector<float>(n, -7.0f),
                std::vector<float>(n, -7.0f)};
}

void expectSame(const Mapped& got, const Mapped& want) {
  ASSERT_EQ(got.idx.size(), want.idx.size());
  for (size_t k = 0; k < want.idx.size(); ++k) {
    EXPECT_EQ(got.idx[k], want.idx[k]) << "point " << k;
    EXPECT_TRUE(sameBits(got.z[k], want.z[k])) << "point " << k;
    EXPECT_EQ(got.w[k], want.w[k]) << "point " << k;
    // Where in the cell: meaningful for the points inside the grid only; the sentinels where
    // the fractions were not asked for.
    if (want.idx[k] < kCells.discard) {
      EXPECT_TRUE(sameBits(got.fu[k], want.fu[k])) << "point " << k;
      EXPECT_TRUE(sameBits(got.fv[k], want.fv[k])) << "point " << k;
    }
  }
}

/// A kernel's fractions of the cell: in [0, 1), and where the point is.
void expectFractionsInCells(const Mapped& got, const std::vector<Eigen::Vector3f>& mapped_xy) {
  for (size_t k = 0; k < got.idx.size(); ++k) {
    if (got.idx[k] >= kCells.discard) continue;
    EXPECT_GE(got.fu[k], 0.0f);
    EXPECT_LT(got.fu[k], 1.0f);
    EXPECT_GE(got.fv[k], 0.0f);
    EXPECT_LT(got.fv[k], 1.0f);
    const int col = got.idx[k] % kCells.grid_cols, row = got.idx[k] / kCells.grid_cols;
    EXPECT_NEAR(kCells.x0 + (col + got.fu[k]) / kCells.inv_res, mapped_xy[k].x(), 1e-4f);
    EXPECT_NEAR(kCells.y0 + (row + got.fv[k]) / kCells.inv_res, mapped_xy[k].y(), 1e-4f);
  }
}

/// A mapping kernel: maps points [from, n) and returns where it stopped.
using PointKernel = size_t (*)(const simd::CellMapping&, const Eigen::Vector3f*, size_t, size_t,
                               const RowMajorPose&, int*, float*, simd::CellFractions);
using WeightedKernel = size_t (*)(const simd::CellMapping&, const WeightedPoint*, size_t, size_t,
                                  const RowMajorPose&, int*, float*, std::uint32_t*,
                                  simd::CellFractions);

/// The kernels in the order HeightGrid dispatches them (widest first), finished by the scalar
/// reference, against the scalar reference alone.
void expectPointKernelsMatchScalar(const std::vector<PointKernel>& kernels, size_t width) {
  std::mt19937 rng = test::seeded(11);
  int inside = 0, outside = 0;
  for (size_t n : edgeLengths()) {
    for (int trial = 0; trial < 4; ++trial) {
      const PointCloud p = somePoints(n, rng);
      const RowMajorPose m = trial == 0 ? RowMajorPose() : somePose(rng);
      Mapped want = mapped(n), got = mapped(n);
      // Every other trial with the fractions of the cell.
      const bool fractions = trial % 2 == 1;
      simd::mapPointsScalar(kCells, p.data(), 0, n, m, want.idx.data(), want.z.data(),
                            want.fractions(fractions));
      size_t k = 0;
      for (PointKernel kernel : kernels)
        k = kernel(kCells, p.data(), k, n, m, got.idx.data(), got.z.data(),
                   got.fractions(fractions));
      EXPECT_EQ(k, n - n % width) << "the widest kernel stops before the last whole vector";
      simd::mapPointsScalar(kCells, p.data(), k, n, m, got.idx.data(), got.z.data(),
                            got.fractions(fractions));
      expectSame(got, want);
      if (fractions) {
        std::vector<Eigen::Vector3f> xy(n);
        for (size_t j = 0; j < n; ++j)
          m.apply(p[j].x(), p[j].y(), p[j].z(), xy[j].x(), xy[j].y(), xy[j].z());
        expectFractionsInCells(got, xy);
      }
      inside += want.inside();
      outside += static_cast<int>(n) - want.inside();
    }
  }
  // Both branches of the cell test were compared.
  EXPECT_GT(inside, 200);
  EXPECT_GT(outside, 200);
}

void expectWeightedKernelsMatchScalar(const std::vector<WeightedKernel>& kernels, size_t width) {
  std::mt19937 rng = test::seeded(12);
  int inside = 0;
  for (size_t n : edgeLengths()) {
    for (int trial = 0; trial < 4; ++trial) {
      const WeightedCloud p = weighted(somePoints(n, rng), rng);
      const RowMajorPose m = somePose(rng);
      Mapped want = mapped(n), got = mapped(n);
      const bool fractions = trial % 2 == 1;
      simd::mapWeightedScalar(kCells, p.data(), 0, n, m, want.idx.data(), want.z.data(),
                              want.w.data(), want.fractions(fractions));
      size_t k = 0;
      for (WeightedKernel kernel : kernels) {
        k = kernel(kCells, p.data(), k, n, m, got.idx.data(), got.z.data(), got.w.data(),
                   got.fractions(fractions));
      }
      EXPECT_EQ(k, n - n % width);
      simd::mapWeightedScalar(kCells, p.data(), k, n, m, got.idx.data(), got.z.data(), got.w.data(),
                              got.fractions(fractions));
      expectSame(got, want);
      inside += want.inside();
    }
  }
  EXPECT_GT(inside, 200);
}

#ifdef DLO_SIMD_AVX2_DISPATCH
#define DLO_SKIP_WITHOUT_AVX2() \
  if (!simd::hasAvx2())         \
  GTEST_SKIP() << "this processor has no AVX2: the AVX2 kernel never runs here"
#endif

#ifdef __SSE2__

TEST(HeightGridKernels, MapPointsSse2IsScalarBitForBit) {
  expectPointKernelsMatchScalar({&simd::mapPointsSse2}, 4);
}

TEST(HeightGridKernels, MapWeightedSse2IsScalarBitForBit) {
  expectWeightedKernelsMatchScalar({&simd::mapWeightedSse2}, 4);
}

#ifdef DLO_SIMD_AVX2_DISPATCH
TEST(HeightGridKernels, MapPointsAvx2ThenSse2IsScalarBitForBit) {
  DLO_SKIP_WITHOUT_AVX2();
  expectPointKernelsMatchScalar({&simd::mapPointsAvx2}, 8);
  expectPointKernelsMatchScalar({&simd::mapPointsAvx2, &simd::mapPointsSse2}, 4);
}

TEST(HeightGridKernels, MapWeightedAvx2ThenSse2IsScalarBitForBit) {
  DLO_SKIP_WITHOUT_AVX2();
  expectWeightedKernelsMatchScalar({&simd::mapWeightedAvx2}, 8);
  expectWeightedKernelsMatchScalar({&simd::mapWeightedAvx2, &simd::mapWeightedSse2}, 4);
}
#endif

TEST(HeightGridKernels, BinRunEndSse2StopsWithinTheRunAndScalarFinishesIt) {
  std::mt19937 rng = test::seeded(13);
  std::uniform_int_distribution<int> run(1, 12);
  for (size_t n : edgeLengths()) {
    // Runs of 1 to 12 equal bins, increasing as along a sweep.
    std::vector<int> bin(n);
    for (size_t k = 0, b = 0; k < n; ++b) {
      for (int r = run(rng); r > 0 && k < n; --r) bin[k++] = static_cast<int>(b);
    }
    for (size_t k = 0; k < n; ++k) {
      const size_t want = simd::binRunEndScalar(bin.data(), k, k + 1, n);
      const size_t stop = simd::binRunEndSse2(bin.data(), k, k + 1, n);
      ASSERT_LE(stop, want) << "the kernel ran past the run at " << k;
      EXPECT_LT(want - stop, 4u) << "the kernel left a whole vector of the run at " << k;
      EXPECT_EQ(simd::binRunEndScalar(bin.data(), k, stop, n), want);
    }
  }
}

/// n cells of one fine row as rasterisation leaves them: most empty (count and sum 0), some
/// clusters of measured cells with fewer or more points than needed, heights of either sign.
struct Row {
  std::vector<std::int32_t> count;
  std::vector<float> sum;
};
Row someRow(size_t n, std::mt19937& rng) {
  std::uniform_int_distribution<int> cluster(0, 5), points(1, 9);
  std::uniform_real_distribution<float> height(-3.0f, 3.0f);
  Row row{std::vector<std::int32_t>(n, 0), std::vector<float>(n, 0.0f)};
  for (size_t c = 0; c < n; ++c) {
    if (cluster(rng) != 0 && (c == 0 || row.count[c - 1] == 0)) continue;
    row.count[c] = points(rng);
    for (int k = 0; k < row.count[c]; ++k) row.sum[c] += height(rng);
  }
  if (n > 3) row.sum[n - 2] = -0.0f;  // a cell whose points sum to -0: its height must be +0
  if (n > 3) row.count[n - 2] = 4;
  return row;
}

struct Finalised {
  std::vector<float> height;
  std::vector<std::uint8_t> valid;
  std::vector<std::uint32_t> pool_count;
  std::vector<float> pool_sum;
  int valid_cells = 0;
};

Finalised finalise(const Row& row, bool pool, bool vector_first) {
  const int n = static_cast<int>(row.count.size());
  // The coarse row already holds the other fine row's pairs.
  Finalised f{std::vector<float>(n, -7.0f), std::vector<std::uint8_t>(n, 7),
              std::vector<std::uint32_t>((n + 1) / 2 + 1, 3u),
              std::vector<float>((n + 1) / 2 + 1, 0.5f), 0};
  const simd::PoolRow coarse{f.pool_count.data(), f.pool_sum.data()};
  const simd::CellSums cells{row.count.data(), row.sum.data(),          n, 3, f.height.data(),
                             f.valid.data(),   pool ? &coarse : nullptr};
  int i = 0;
  if (vector_first) i = simd::finaliseCellsSse2(cells, 0, f.valid_cells);
  EXPECT_EQ(i, vector_first ? n - n % 16 : 0);
  simd::finaliseCellsScalar(cells, i, f.valid_cells);
  return f;
}

TEST(HeightGridKernels, FinaliseCellsSse2IsScalarBitForBit) {
  std::mt19937 rng = test::seeded(14);
  int valid = 0;
  std::vector<size_t> lengths = edgeLengths();
  lengths.push_back(400);
  lengths.push_back(401);
  for (size_t n : lengths) {
    for (bool pool : {false, true}) {
      const Row row = someRow(n, rng);
      const Finalised want = finalise(row, pool, false);
      const Finalised got = finalise(row, pool, true);
      EXPECT_EQ(got.valid_cells, want.valid_cells) << n << " cells";
      EXPECT_EQ(got.valid, want.valid) << n << " cells";
      EXPECT_EQ(got.pool_count, want.pool_count) << n << " cells";
      for (size_t c = 0; c < n; ++c) {
        EXPECT_TRUE(sameBits(got.height[c], want.height[c])) << "cell " << c << " of " << n;
      }
      for (size_t j = 0; j < want.pool_sum.size(); ++j) {
        EXPECT_TRUE(sameBits(got.pool_sum[j], want.pool_sum[j])) << "coarse " << j << " of " << n;
      }
      valid += want.valid_cells;
    }
  }
  EXPECT_GT(valid, 100);
}

TEST(HeightGridKernels, PullColumnsSse2IsScalarBitForBit) {
  std::mt19937 rng = test::seeded(15);
  std::bernoulli_distribution supported(0.6);
  std::uniform_real_distribution<float> height(-3.0f, 3.0f);
  int ok = 0, not_ok = 0;
  for (size_t coarse : edgeLengths()) {
    // Two padded coarse rows (support 0 or 1, support * height), blended vertically as
    // interpolateRow() blends them for an even and an odd fine row.
    const size_t pc = coarse + 3;
    std::vector<float> s(2 * pc), h(2 * pc);
    for (size_t k = 0; k < s.size(); ++k) {
      s[k] = supported(rng) ? 1.0f : 0.0f;
      h[k] = s[k] * height(rng);
    }
    for (float b : {0.75f, 0.25f}) {
      std::vector<float> vs(pc), vh(pc);
      for (size_t j = 0; j < pc; ++j) {
        vs[j] = (1 - b) * s[j] + b * s[j + pc];
        vh[j] = (1 - b) * h[j] + b * h[j + pc];
      }
      for (int j0 : {0, 1}) {
        const int j_end = static_cast<int>(coarse);
        if (j0 > j_end) continue;
        std::vector<float> want_value(2 * pc, -7.0f), want_ok(2 * pc, -7.0f);
        std::vector<float> got_value = want_value, got_ok = want_ok;
        simd::pullColumnsScalar(vs.data(), vh.data(), j0, j_end, want_value.data(), want_ok.data());
        const int j =
            simd::pullColumnsSse2(vs.data(), vh.data(), j0, j_end, got_value.data(), got_ok.data());
        EXPECT_EQ(j_end - j, (j_end - j0) % 4);
        simd::pullColumnsScalar(vs.data(), vh.data(), j, j_end, got_value.data(), got_ok.data());
        for (size_t c = 0; c < want_value.size(); ++c) {
          EXPECT_TRUE(sameBits(got_value[c], want_value[c])) << "fine column " << c;
          EXPECT_TRUE(sameBits(got_ok[c], want_ok[c])) << "fine column " << c;
          ok += want_ok[c] == 1.0f ? 1 : 0;
          not_ok += want_ok[c] == 0.0f ? 1 : 0;
        }
      }
    }
  }
  EXPECT_GT(ok, 100);
  EXPECT_GT(not_ok, 100);
}

#endif  // __SSE2__

}  // namespace
}  // namespace dlo
