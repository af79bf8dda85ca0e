// Placing cells against the reference's centroid offsets for the Gauss-Newton iterations: the
// SSE2 kernel (libs/core/src/simd/place_cells_sse2.cpp) against its scalar reference, on
// fixed-seed random lattices and cells. The kernel promises the same results bit for bit: the
// iterations must not change trajectories.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "dlo/core/grid_geometry.h"
#include "kernel_test_util.h"
#include "simd/place_cells_kernels.h"

namespace dlo {
namespace {

using test::sameBits;

/// Offsets within +-`spread` cells of each centre, on a rows x cols lattice of 0.1 m. Large
/// spreads fold the lattice (neighbouring centroids cross), where Newton's method stops.
std::vector<Eigen::Vector2f> offsets(int rows, int cols, float spread, std::mt19937& rng) {
  std::uniform_real_distribution<float> o(-spread * 0.1f, spread * 0.1f);
  std::vector<Eigen::Vector2f> out(static_cast<size_t>(rows) * cols);
  for (Eigen::Vector2f& v : out) v = Eigen::Vector2f(o(rng), o(rng));
  return out;
}

/// Cells over the lattice and a margin of a metre around it (where offsets are zero), their
/// own offsets within half a cell, plus a NaN and the edges of the cell centres.
void someCells(const GridGeometry& g, size_t n, std::mt19937& rng, std::vector<SelectedCell>& cells,
               std::vector<Eigen::Vector2f>& own) {
  std::uniform_real_distribution<float> x(static_cast<float>(g.x_min) - 1.0f,
                                          static_cast<float>(g.x_min + g.cols * 0.1) + 1.0f);
  std::uniform_real_distribution<float> y(static_cast<float>(g.y_min) - 1.0f,
                                          static_cast<float>(g.y_min + g.rows * 0.1) + 1.0f);
  std::uniform_real_distribution<float> h(-1.0f, 3.0f), o(-0.05f, 0.05f);
  cells.clear();
  own.clear();
  for (size_t k = 0; k < n; ++k) {
    cells.push_back(SelectedCell{x(rng), y(rng), h(rng), k % 7 == 0});
    own.emplace_back(o(rng), o(rng));
  }
  for (const SelectedCell& c : test::edgeCells(g)) {
    cells.push_back(c);
    own.emplace_back(0.0f, 0.0f);
  }
}

bool same(float a, float b) {
  return sameBits(a, b) || (std::isnan(a) && std::isnan(b));
}

/// The kernel on cells [0, n) finished by the scalar reference, against the scalar reference:
/// cold and warm starts, with and without the warm-start output, the identity and a pose.
TEST(PlaceCellsKernels, Sse2IsScalarBitForBit) {
#ifndef __SSE2__
  GTEST_SKIP() << "no SSE2 kernel on this processor";
#else
  std::mt19937 rng = test::seeded(11);
  int moved = 0;
  for (const auto& size : {std::pair<int, int>{1, 1}, {2, 3}, {40, 56}}) {
    const GridGeometry g = GridGeometry::centred(size.second, size.first, 0.1);
    for (float spread : {0.3f, 1.5f}) {
      const std::vector<Eigen::Vector2f> lattice_offsets =
          offsets(size.first, size.second, spread, rng);
      const simd::OffsetLattice lattice = simd::offsetLattice(g, lattice_offsets.data());
      for (size_t extra : test::edgeLengths()) {
        std::vector<SelectedCell> cells;
        std::vector<Eigen::Vector2f> own;
        someCells(g, 300 + extra, rng, cells, own);
        const size_t n = cells.size();
        for (int pose = 0; pose < 2; ++pose) {
          const auto [R, t] = test::testPose(pose);
          for (int mode = 0; mode < 3; ++mode) {
            // 0: no warm output; 1: cold start into a warm output; 2: warm start from it.
            std::uniform_real_distribution<float> w(-0.03f, 0.03f);
            std::vector<Eigen::Vector2f> warm_in(n);
            for (Eigen::Vector2f& v : warm_in) v = Eigen::Vector2f(w(rng), w(rng));
            std::vector<Eigen::Vector2f> want_w = warm_in, got_w = warm_in;
            Eigen::Vector2f* ww = mode == 0 ? nullptr : want_w.data();
            Eigen::Vector2f* gw = mode == 0 ? nullptr : got_w.data();
            const bool warm_start = mode == 2;
            std::vector<SelectedCell> want(n), got(n);
            simd::placeCellsScalar(lattice, cells.data(), own.data(), 0, n, R, t, warm_start, ww,
                                   want.data());
            const size_t k = simd::placeCellsSse2(lattice, cells.data(), own.data(), 0, n, R, t,
                                                  warm_start, gw, got.data());
            ASSERT_EQ(k, n - n % 4);
            simd::placeCellsScalar(lattice, cells.data(), own.data(), k, n, R, t, warm_start, gw,
                                   got.data());
            for (size_t i = 0; i < n; ++i) {
              ASSERT_TRUE(same(got[i].x, want[i].x)) << "cell " << i << " mode " << mode;
              ASSERT_TRUE(same(got[i].y, want[i].y)) << "cell " << i << " mode " << mode;
              ASSERT_TRUE(sameBits(got[i].h, want[i].h)) << "cell " << i;
              ASSERT_EQ(got[i].ground, want[i].ground) << "cell " << i;
              if (mode != 0) {
                ASSERT_TRUE(same(got_w[i].x(), want_w[i].x())) << "cell " << i;
                ASSERT_TRUE(same(got_w[i].y(), want_w[i].y())) << "cell " << i;
              }
              const float dx = want[i].x - (cells[i].x + own[i].x());
              moved += std::isfinite(dx) && std::fabs(dx) > 1e-4f ? 1 : 0;
            }
          }
        }
      }
    }
  }
  // The offsets moved cells (the comparison is not between two copies of the input).
  EXPECT_GT(moved, 1000);
#endif
}

/// One Newton step from where a cell stood at the previous pose (kWarmNewtonSteps) places it
/// nearly where the full solution from its own position does, after a pose change of the size
/// that late Gauss-Newton iterations make (millimetres, hundredths of a degree): the iterations
/// may stop refining the places without moving the answer they converge to.
TEST(PlaceCellsKernels, OneWarmStepNearlySolvesASmallMotion) {
  std::mt19937 rng = test::seeded(12);
  const GridGeometry g = GridGeometry::centred(56, 40, 0.1);
  const std::vector<Eigen::Vector2f> lattice_offsets = offsets(g.rows, g.cols, 0.3f, rng);
  const simd::OffsetLattice lattice = simd::offsetLattice(g, lattice_offsets.data());
  std::vector<SelectedCell> cells;
  std::vector<Eigen::Vector2f> own;
  someCells(g, 2000, rng, cells, own);
  const size_t n = cells.size();
  const Eigen::Matrix3f R0 = Eigen::Matrix3f::Identity();
  const Eigen::Vector3f t0(0.2f, -0.1f, 0.0f);
  for (const float step : {0.001f, 0.005f}) {
    // The previous iteration's places, then the next pose: `step` metres and step / 10 rad.
    std::vector<Eigen::Vector2f> warm(n);
    std::vector<SelectedCell> before(n), warm_placed(n), cold_placed(n);
    simd::placeCellsScalar(lattice, cells.data(), own.data(), 0, n, R0, t0, false, warm.data(),
                           before.data());
    const Eigen::Matrix3f R1 = Eigen::AngleAxisf(0.1f * step, Eigen::Vector3f::UnitZ()).matrix();
    const Eigen::Vector3f t1 = t0 + Eigen::Vector3f(step, -0.5f * step, 0.0f);
    simd::placeCellsScalar(lattice, cells.data(), own.data(), 0, n, R1, t1, true, warm.data(),
                           warm_placed.data());
    simd::placeCellsScalar(lattice, cells.data(), own.data(), 0, n, R1, t1, false, nullptr,
                           cold_placed.data());
    std::vector<float> error, moved;
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector2f c(cold_placed[i].x, cold_placed[i].y);
      const Eigen::Vector2f w(warm_placed[i].x, warm_placed[i].y);
      const Eigen::Vector2f b(before[i].x, before[i].y);
      if (!c.allFinite()) continue;
      error.push_back((w - c).norm());
      moved.push_back((b - c).norm());
    }
    ASSERT_GT(error.size(), n / 2);
    std::sort(error.begin(), error.end());
    std::sort(moved.begin(), moved.end());
    const size_t p95 = error.size() * 95 / 100;
    // The places themselves moved with the pose (beyond what the step leaves)...
    EXPECT_GT(moved[p95], 0.2f * step) << "step " << step;
    // ...and the one step left a small fraction of that. A cell whose step crosses into the
    // next cell of the lattice, where the offsets' slope changes, keeps an error of first order,
    // still below the motion.
    EXPECT_LT(error[p95], 0.02f * moved[p95]) << "step " << step;
    EXPECT_LT(error.back(), 0.5f * step) << "step " << step;
  }
}

}  // namespace
}  // namespace dlo
