// HeightGrid: rasterisation statistics, the 3-point rule, pyramid pooling and hole filling.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <utility>

#include "dlo/core/height_grid.h"
#include "dlo/core/weighted_cloud.h"

namespace dlo {
namespace {

// A 10 x 10 grid of 1 m cells centred on the origin: cell (r, c) covers
// x in [c - 5, c - 4), y in [r - 5, r - 4).
GridGeometry tenByTen() {
  return GridGeometry::centred(10, 10, 1.0);
}

PointCloud pointsInCell(int row, int col, const std::vector<float>& heights) {
  PointCloud pts;
  for (size_t k = 0; k < heights.size(); ++k) {
    const float dx = 0.1f + 0.8f * static_cast<float>(k) / static_cast<float>(heights.size());
    pts.emplace_back(static_cast<float>(col - 5) + dx, static_cast<float>(row - 5) + 0.5f,
                     heights[k]);
  }
  return pts;
}

TEST(HeightGrid, IgnoresCellsWithFewerThanThreePoints) {
  PointCloud pts = pointsInCell(2, 3, {1.0f, 2.0f});
  const PointCloud three = pointsInCell(4, 4, {1.0f, 2.0f, 3.0f});
  pts.insert(pts.end(), three.begin(), three.end());
  const HeightGrid g = HeightGrid::fromPoints(pts, tenByTen(), 3, -10, 10);
  EXPECT_FALSE(g.isValid(2, 3));
  EXPECT_EQ(g.count(2, 3), 2u);
  EXPECT_TRUE(g.isValid(4, 4));
  EXPECT_EQ(g.validCellCount(), 1);
}

TEST(HeightGrid, CellHeightIsTheMeanOfItsPoints) {
  const HeightGrid g =
      HeightGrid::fromPoints(pointsInCell(7, 1, {0.5f, 1.5f, 4.0f, -2.0f}), tenByTen(), 3, -10, 10);
  ASSERT_TRUE(g.isValid(7, 1));
  EXPECT_FLOAT_EQ(g.height(7, 1), 1.0f);
  EXPECT_EQ(g.count(7, 1), 4u);
}

TEST(HeightGrid, SkipsNonFinitePointsAndPointsOutsideTheWindowOrHeightBand) {
  PointCloud pts = pointsInCell(5, 5, {1.0f, 1.0f, 1.0f});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  pts.emplace_back(0.5f, 0.5f, nan);
  pts.emplace_back(nan, 0.5f, 1.0f);
  pts.emplace_back(0.5f, inf, 1.0f);
  pts.emplace_back(0.5f, 0.5f, 50.0f);   // above max_z
  pts.emplace_back(0.5f, 0.5f, -50.0f);  // below min_z
  pts.emplace_back(5.0f, 0.5f, 1.0f);    // x == x_max: outside
  pts.emplace_back(-5.01f, 0.5f, 1.0f);  // left of x_min
  const HeightGrid g = HeightGrid::fromPoints(pts, tenByTen(), 3, -10, 10);
  EXPECT_EQ(g.count(5, 5), 3u);
  EXPECT_FLOAT_EQ(g.height(5, 5), 1.0f);
  EXPECT_EQ(g.validCellCount(), 1);
}

TEST(HeightGrid, PointsOnCellBoundariesGoToTheUpperCell) {
  PointCloud pts(3, Eigen::Vector3f(0.0f, 0.0f, 2.0f));  // x = 0 is the left edge of column 5
  const HeightGrid g = HeightGrid::fromPoints(pts, tenByTen(), 3, -10, 10);
  EXPECT_TRUE(g.isValid(5, 5));
}

TEST(HeightGrid, CoarserLevelIsTheMeanOfAllPointsOfItsFourCells) {
  PointCloud pts = pointsInCell(0, 0, {1.0f, 1.0f, 1.0f, 1.0f});  // 4 points, mean 1
  const PointCloud b = pointsInCell(1, 1, {4.0f, 4.0f});          // 2 points: invalid alone
  pts.insert(pts.end(), b.begin(), b.end());
  const HeightGrid fine = HeightGrid::fromPoints(pts, tenByTen(), 3, -10, 10);
  EXPECT_FALSE(fine.isValid(1, 1));
  const HeightGrid coarse = fine.coarser();
  EXPECT_EQ(coarse.cols(), 5);
  EXPECT_DOUBLE_EQ(coarse.resolution(), 2.0);
  ASSERT_TRUE(coarse.isValid(0, 0));
  EXPECT_EQ(coarse.count(0, 0), 6u);
  EXPECT_FLOAT_EQ(coarse.height(0, 0), (4 * 1.0f + 2 * 4.0f) / 6.0f);
}

TEST(HeightGrid, CoarserOfAnOddSizedGridKeepsTheLastColumn) {
  const GridGeometry geo{0.0, 0.0, 1.0, 5, 3};
  PointCloud pts(3, Eigen::Vector3f(4.5f, 2.5f, 7.0f));  // last column and row
  const HeightGrid coarse = HeightGrid::fromPoints(pts, geo, 3, -10, 10).coarser();
  EXPECT_EQ(coarse.cols(), 3);
  EXPECT_EQ(coarse.rows(), 2);
  EXPECT_TRUE(coarse.isValid(1, 2));
}

TEST(HeightGrid, FillHolesInterpolatesTheCoarserLevelWithoutTouchingMeasuredCells) {
  // Two measured cells two columns apart; the empty one between them gets a height from the
  // coarser level, the measured ones keep their own mean, and cells far from data stay empty.
  PointCloud pts = pointsInCell(4, 3, {1.0f, 1.0f, 1.0f});
  const PointCloud b = pointsInCell(4, 5, {3.0f, 3.0f, 3.0f});
  pts.insert(pts.end(), b.begin(), b.end());
  HeightGrid fine = HeightGrid::fromPoints(pts, tenByTen(), 3, -10, 10);
  const HeightGrid coarse = fine.coarser();
  fine.fillHolesFrom(coarse);
  EXPECT_FLOAT_EQ(fine.height(4, 3), 1.0f);
  EXPECT_FLOAT_EQ(fine.height(4, 5), 3.0f);
  EXPECT_FALSE(fine.isValid(4, 4));
  ASSERT_TRUE(fine.hasSupport(4, 4));
  EXPECT_GE(fine.height(4, 4), 1.0f);
  EXPECT_LE(fine.height(4, 4), 3.0f);
  EXPECT_FALSE(fine.hasSupport(0, 9));
  EXPECT_FALSE(fine.hasSupport(9, 0));
}

TEST(HeightGrid, FillHolesIsTheSupportWeightedBilinearInterpolationOfTheCoarserLevel) {
  // Odd sizes (the vectorised interpolation works eight fine columns at a time) and scattered
  // cells of random heights; every empty cell is checked against the interpolation written out.
  for (const auto& [cols, rows] : {std::pair<int, int>{37, 23}, {64, 9}, {5, 40}}) {
    const GridGeometry geo{-1.0, 2.0, 0.5, cols, rows};
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> col(0, cols - 1), row(0, rows - 1);
    std::uniform_real_distribution<float> height(-2.0f, 2.0f);
    PointCloud pts;
    for (int i = 0; i < cols * rows / 6; ++i) {
      // Three points in a random cell.
      const int c = col(rng), r = row(rng);
      for (int k = 0; k < 3; ++k) {
        pts.emplace_back(static_cast<float>(geo.x_min + (c + 0.2 + 0.3 * k) * geo.resolution),
                         static_cast<float>(geo.y_min + (r + 0.5) * geo.resolution), height(rng));
      }
    }
    const HeightGrid raw = HeightGrid::fromPoints(pts, geo, 3, -10, 10);
    const HeightGrid coarse = raw.coarser();
    HeightGrid filled = raw;
    filled.fillHolesFrom(coarse);
    int checked = 0;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        if (raw.isValid(r, c)) {
          ASSERT_TRUE(filled.hasSupport(r, c));
          ASSERT_EQ(filled.height(r, c), raw.height(r, c));
          continue;
        }
        // The fine centre in coarse cell units, and its four surrounding coarse cells.
        const double u = (c + 0.5) / 2.0 - 0.5, v = (r + 0.5) / 2.0 - 0.5;
        const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
        double w = 0.0, wh = 0.0;
        for (int dv = 0; dv < 2; ++dv) {
          for (int du = 0; du < 2; ++du) {
            const int cu = u0 + du, cv = v0 + dv;
            if (cu < 0 || cv < 0 || cu >= coarse.cols() || cv >= coarse.rows() ||
                !coarse.isValid(cv, cu)) {
              continue;
            }
            const double k = (du ? u - u0 : 1.0 - (u - u0)) * (dv ? v - v0 : 1.0 - (v - v0));
            w += k;
            wh += k * coarse.height(cv, cu);
          }
        }
        ASSERT_EQ(filled.hasSupport(r, c), w >= 0.5) << r << ", " << c;
        if (w >= 0.5) {
          ASSERT_NEAR(filled.height(r, c), wh / w, 1e-5) << r << ", " << c;
          ++checked;
        }
      }
    }
    EXPECT_GT(checked, cols * rows / 10);
  }
}

TEST(HeightGrid, RasterisationPutsEveryPointInTheCellOfItsCoordinates) {
  // Random points in and around the grid, some outside the height band or not finite, in
  // counts that leave tails for every vector width; each cell's count and height sum must be
  // those of a plain loop (the vector paths, SSE2 or AVX2 where the processor has it, follow
  // the scalar operations exactly).
  const GridGeometry geo{-3.0, -2.0, 0.25, 23, 17};
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> x(-4.0f, 4.0f), y(-3.0f, 3.0f), z(-2.0f, 2.0f);
  for (size_t count : {0u, 1u, 7u, 8u, 13u, 1001u, 20003u}) {
    PointCloud pts(count);
    for (size_t i = 0; i < count; ++i) {
      pts[i] = Eigen::Vector3f(x(rng), y(rng), z(rng));
      if (i % 97 == 5) pts[i].x() = std::numeric_limits<float>::quiet_NaN();
    }
    const HeightGrid g = HeightGrid::fromPoints(pts, geo, 1, -1.5, 1.5);
    // The weighted path (keyframes, local maps) with unit weights and no motion: the same.
    HeightGrid weighted;
    weighted.rasterise(unitWeights(pts), Eigen::Isometry3d::Identity(), geo, 1, -1.5, 1.5);
    std::vector<std::uint32_t> n(static_cast<size_t>(geo.cellCount()), 0u);
    std::vector<float> sum(n.size(), 0.0f);
    const float x0 = static_cast<float>(geo.x_min), y0 = static_cast<float>(geo.y_min);
    const float inv = static_cast<float>(1.0 / geo.resolution);
    for (const Eigen::Vector3f& p : pts) {
      const float u = (p.x() - x0) * inv, v = (p.y() - y0) * inv;
      if (!(u >= 0.0f && u < geo.cols && v >= 0.0f && v < geo.rows && p.z() >= -1.5f &&
            p.z() <= 1.5f)) {
        continue;
      }
      const size_t cell = static_cast<size_t>(static_cast<int>(v) * geo.cols + static_cast<int>(u));
      n[cell] += 1;
      sum[cell] += p.z();
    }
    for (int r = 0; r < geo.rows; ++r) {
      for (int c = 0; c < geo.cols; ++c) {
        const size_t cell = static_cast<size_t>(r * geo.cols + c);
        ASSERT_EQ(g.count(r, c), n[cell]) << count << " points, cell " << r << ", " << c;
        ASSERT_EQ(weighted.count(r, c), n[cell]) << count << " points, cell " << r << ", " << c;
        if (n[cell] > 0) {
          ASSERT_EQ(g.height(r, c), sum[cell] / static_cast<float>(n[cell]) + 0.0f);
          ASSERT_EQ(weighted.height(r, c), g.height(r, c));
        }
      }
    }
  }
}

/// Same geometry, counts, heights and flags in every cell, to the bit.
void expectSameGrid(const HeightGrid& a, const HeightGrid& b) {
  ASSERT_EQ(a.cols(), b.cols());
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.resolution(), b.resolution());
  ASSERT_EQ(a.validCellCount(), b.validCellCount());
  for (int r = 0; r < a.rows(); ++r) {
    for (int c = 0; c < a.cols(); ++c) {
      ASSERT_EQ(a.count(r, c), b.count(r, c)) << "cell " << r << ", " << c;
      ASSERT_EQ(std::memcmp(&a.heights()[r * a.cols() + c], &b.heights()[r * b.cols() + c],
                            sizeof(float)),
                0)
          << "cell " << r << ", " << c;
      ASSERT_EQ(a.isValid(r, c), b.isValid(r, c)) << "cell " << r << ", " << c;
    }
  }
}

TEST(HeightGrid, ALevelPooledWhileRasterisingEqualsPoolFrom) {
  // rasterise(..., &coarser) pools the coarser level in the same pass as it finalises the grid,
  // sixteen cells at a time and the rest of each row one pair at a time: every cell of both
  // levels must be what rasterise() then poolFrom() give, for grids whose rows are whole
  // vectors, have tails, or an odd last column, for sweeps, weighted clouds and cell fillers.
  std::mt19937 rng(5);
  for (const GridGeometry& geo :
       {GridGeometry{-3.0, -2.0, 0.25, 23, 17}, GridGeometry{-4.0, -4.0, 0.1, 80, 80},
        GridGeometry{-5.0, -2.0, 0.1, 100, 41}}) {
    SCOPED_TRACE(std::to_string(geo.cols) + " x " + std::to_string(geo.rows));
    const float x0 = static_cast<float>(geo.x_min), y0 = static_cast<float>(geo.y_min);
    const float width = static_cast<float>(geo.cols * geo.resolution);
    const float height = static_cast<float>(geo.rows * geo.resolution);
    std::uniform_real_distribution<float> x(x0 - 1.0f, x0 + width + 1.0f);
    std::uniform_real_distribution<float> y(y0 - 1.0f, y0 + height + 1.0f);
    std::uniform_real_distribution<float> z(-2.0f, 2.0f);
    PointCloud pts(20000);
    for (Eigen::Vector3f& p : pts) p = Eigen::Vector3f(x(rng), y(rng), z(rng));
    // Some empty stretches, so that groups without points are skipped.
    for (Eigen::Vector3f& p : pts) {
      if (p.y() > 0.0f && p.y() < 0.5f) p.x() = x0 + 0.01f;
    }
    HeightGrid fine, coarse, pooled_fine, pooled;
    fine.rasterise(pts, SweepMotion(), geo, 2, -1.5, 1.5);
    coarse.poolFrom(fine);
    pooled_fine.rasterise(pts, SweepMotion(), geo, 2, -1.5, 1.5, &pooled);
    expectSameGrid(pooled_fine, fine);
    expectSameGrid(pooled, coarse);

    WeightedCloud weighted = unitWeights(pts);
    for (size_t i = 0; i < weighted.size(); ++i) weighted[i].n = 1 + static_cast<unsigned>(i % 3);
    const std::vector<PosedCloud> parts{PosedCloud{&weighted, Eigen::Isometry3d::Identity()}};
    fine.rasterise(parts, geo, 3, -1.5, 1.5);
    coarse.poolFrom(fine);
    pooled_fine.rasterise(parts, geo, 3, -1.5, 1.5, &pooled);
    expectSameGrid(pooled_fine, fine);
    expectSameGrid(pooled, coarse);

    const auto fill = [&](std::uint32_t* count, float* sum) {
      for (int i = 0; i < geo.cellCount(); i += 3) {
        count[i] = static_cast<std::uint32_t>(i % 5);
        sum[i] = 0.5f * static_cast<float>(i % 7) - 1.0f;
      }
    };
    fine.accumulateCells(geo, 2, fill);
    coarse.poolFrom(fine);
    pooled_fine.accumulateCells(geo, 2, fill, &pooled);
    expectSameGrid(pooled_fine, fine);
    expectSameGrid(pooled, coarse);
  }
}

TEST(HeightGrid, FillHolesRejectsALevelThatIsNotItsOwnCoarser) {
  HeightGrid fine = HeightGrid::fromPoints({}, tenByTen(), 3, -10, 10);
  const HeightGrid other = HeightGrid::fromPoints({}, GridGeometry::centred(5, 5, 3.0), 3, -10, 10);
  EXPECT_THROW(fine.fillHolesFrom(other), std::invalid_argument);
}

TEST(HeightGrid, FromCellsTakesMeanHeightsAndCounts) {
  std::vector<float> h(100, 0.0f);
  std::vector<std::uint32_t> n(100, 0u);
  h[12] = 2.5f;
  n[12] = 3;
  h[13] = std::numeric_limits<float>::quiet_NaN();
  n[13] = 10;
  h[14] = 1.0f;
  n[14] = 2;
  const HeightGrid g = HeightGrid::fromCells(tenByTen(), h, n, 3);
  EXPECT_TRUE(g.isValid(1, 2));
  EXPECT_FLOAT_EQ(g.height(1, 2), 2.5f);
  EXPECT_FALSE(g.isValid(1, 3));  // NaN height
  EXPECT_FALSE(g.isValid(1, 4));  // too few points
  EXPECT_EQ(g.validCellCount(), 1);
}

TEST(HeightGrid, HeightImageHasNaNOnInvalidCells) {
  const HeightGrid g =
      HeightGrid::fromPoints(pointsInCell(2, 6, {1.0f, 2.0f, 3.0f}), tenByTen(), 3, -10, 10);
  const cv::Mat img = g.heightImage();
  ASSERT_EQ(img.rows, 10);
  ASSERT_EQ(img.cols, 10);
  EXPECT_FLOAT_EQ(img.at<float>(2, 6), 2.0f);
  EXPECT_TRUE(std::isnan(img.at<float>(0, 0)));
}

}  // namespace
}  // namespace dlo
