// Sampling the reference for the Gauss-Newton linearisation: the SSE2 kernel
// (libs/core/src/simd/sample_cells_sse2.cpp) against its scalar reference, and the blend inside
// HeightSampler::sample() against its scalar form, on fixed-seed random grids and points. Both
// promise the same results bit for bit: the linearisation must not change trajectories.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <utility>

#include "dlo/core/height_grid.h"
#include "kernel_test_util.h"
#include "simd/sample_cells_kernels.h"

namespace dlo {
namespace {

using test::sameBits;

/// A sampler over a rows x cols grid of 0.1 m with a bumpy surface and holes (cells without
/// points), so that some samples lack a valid gradient.
HeightSampler sampler(int rows, int cols, std::mt19937& rng) {
  const GridGeometry geo = GridGeometry::centred(cols, rows, 0.1);
  std::uniform_real_distribution<float> height(-1.0f, 3.0f);
  std::bernoulli_distribution hole(0.04);
  std::vector<float> h(geo.cellCount());
  std::vector<std::uint32_t> n(geo.cellCount());
  for (int i = 0; i < geo.cellCount(); ++i) {
    h[i] = height(rng);
    n[i] = hole(rng) ? 0u : 4u;
  }
  HeightGrid grid = HeightGrid::fromCells(geo, h, n, 3);
  GradientField field;
  computeGradients(grid, field);
  return HeightSampler(geo, std::move(field));
}

/// Selected cells over the grid and a margin around it, plus a NaN and the edges of the cell
/// centres, and padding up to a multiple of four.
std::vector<SelectedCell> someCells(const GridGeometry& g, size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> x(static_cast<float>(g.x_min) - 0.5f,
                                          static_cast<float>(g.x_min + g.cols * 0.1) + 0.5f);
  std::uniform_real_distribution<float> y(static_cast<float>(g.y_min) - 0.5f,
                                          static_cast<float>(g.y_min + g.rows * 0.1) + 0.5f);
  std::uniform_real_distribution<float> h(-1.0f, 3.0f);
  std::vector<SelectedCell> cells;
  for (size_t k = 0; k < n; ++k) cells.push_back(SelectedCell{x(rng), y(rng), h(rng), false});
  for (const SelectedCell& c : test::edgeCells(g)) cells.push_back(c);
  return cells;
}

/// The kernel on cells [0, n) finished by the scalar reference, against the scalar reference.
TEST(SampleCellsKernels, Sse2IsScalarBitForBit) {
#ifndef __SSE2__
  GTEST_SKIP() << "no SSE2 kernel on this processor";
#else
  std::mt19937 rng = test::seeded(7);
  int valid = 0, invalid = 0;
  // Grids too small to interpolate in (no lane can be inside), and ordinary ones.
  for (const auto& size : {std::pair<int, int>{1, 1}, {1, 5}, {2, 2}, {3, 7}, {64, 48}}) {
    const HeightSampler s = sampler(size.first, size.second, rng);
    for (size_t extra : test::edgeLengths()) {
      const std::vector<SelectedCell> cells = someCells(s.geometry(), 1000 + extra, rng);
      // The identity (q = p exactly) and a pose like a registration's.
      for (int pose = 0; pose < 2; ++pose) {
        const auto [R, t] = test::testPose(pose);
        const size_t n = cells.size();
        std::vector<simd::CellSample> want(n), got(n);
        simd::sampleCellsScalar(s, cells.data(), 0, n, R, t, want.data());
        const size_t k = simd::sampleCellsSse2(s, cells.data(), 0, n, R, t, got.data());
        ASSERT_EQ(k, n - n % 4);
        simd::sampleCellsScalar(s, cells.data(), k, n, R, t, got.data());
        for (size_t i = 0; i < n; ++i) {
          for (int j = 0; j < 3; ++j) {
            // NaN in, NaN out; else the same bits.
            EXPECT_TRUE(sameBits(got[i].q(j), want[i].q(j)) ||
                        (std::isnan(got[i].q(j)) && std::isnan(want[i].q(j))))
                << "cell " << i;
          }
          ASSERT_EQ(got[i].s.ok, want[i].s.ok) << "cell " << i << " at " << cells[i].x;
          if (want[i].s.ok == 0.0f) {
            ++invalid;
            continue;  // h, gx and gy unspecified
          }
          ++valid;
          EXPECT_TRUE(sameBits(got[i].s.h, want[i].s.h)) << "cell " << i;
          EXPECT_TRUE(sameBits(got[i].s.gx, want[i].s.gx)) << "cell " << i;
          EXPECT_TRUE(sameBits(got[i].s.gy, want[i].s.gy)) << "cell " << i;
        }
      }
    }
  }
  // Both outcomes were exercised.
  EXPECT_GT(valid, 1000);
  EXPECT_GT(invalid, 1000);
#endif
}

TEST(SampleCellsKernels, BlendInsideSampleIsScalarBitForBit) {
#ifndef __SSE2__
  GTEST_SKIP() << "no SSE2 blend on this processor";
#else
  std::mt19937 rng = test::seeded(8);
  std::uniform_real_distribution<float> fraction(0.0f, 1.0f), value(-5.0f, 5.0f);
  int differ_from_naive_order = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // Two rows of two cells (h gx gy ok), as sample() finds them in the gradient field.
    GradientCell cells[4];
    for (GradientCell& c : cells) c = GradientCell{value(rng), value(rng), value(rng), 1.0f};
    const float a = fraction(rng), b = fraction(rng);
    const float w00 = (1 - a) * (1 - b), w01 = a * (1 - b), w10 = (1 - a) * b, w11 = a * b;
    HeightSample want, got;
    detail::blendCellsScalar(w00, w01, w10, w11, cells, cells + 2, want);
    detail::blendCellsSse2(w00, w01, w10, w11, cells, cells + 2, got);
    ASSERT_TRUE(sameBits(got.h, want.h)) << trial;
    ASSERT_TRUE(sameBits(got.gx, want.gx)) << trial;
    ASSERT_TRUE(sameBits(got.gy, want.gy)) << trial;
    // The order of the sum matters at this precision: the comparison can tell orders apart.
    const float other = w11 * cells[3].h + w10 * cells[2].h + w01 * cells[1].h + w00 * cells[0].h;
    differ_from_naive_order += sameBits(other, want.h) ? 0 : 1;
  }
  EXPECT_GT(differ_from_naive_order, 100);
#endif
}

}  // namespace
}  // namespace dlo
