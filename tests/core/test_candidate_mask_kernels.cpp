// selectHighGradientCells()'s candidate test: the SSE2 kernel (libs/core/src/simd/
// candidate_mask_sse2.cpp) against its scalar reference on fixed-seed random rows. The kernel
// promises the same flags, so the comparison is exact.
#include <gtest/gtest.h>

#include "kernel_test_util.h"
#include "simd/candidate_mask_kernels.h"

namespace dlo {
namespace {

TEST(CandidateMaskKernels, Sse2IsScalarExactly) {
#ifndef __SSE2__
  GTEST_SKIP() << "no SSE2 kernel on this processor";
#else
  std::mt19937 rng = test::seeded(51);
  // Squared gradients as the selection computes them: -1 where a neighbour lacks a height,
  // else from 0 up, some exactly at the threshold.
  std::uniform_real_distribution<float> gradient(0.0f, 0.5f);
  std::uniform_int_distribution<int> kind(0, 4);
  std::bernoulli_distribution measured(0.5);
  const float min_sq = 0.2f * 0.2f;
  std::vector<size_t> lengths = test::edgeLengths();
  lengths.push_back(399);
  int candidates = 0, rejected = 0;
  for (size_t n : lengths) {
    for (int from : {0, 1}) {
      if (static_cast<size_t>(from) > n) continue;
      std::vector<float> mag(n);
      std::vector<std::uint8_t> cells(n);
      for (size_t c = 0; c < n; ++c) {
        const int k = kind(rng);
        mag[c] = k == 0 ? -1.0f : k == 1 ? min_sq : gradient(rng);
        cells[c] = measured(rng) ? 1 : 0;
      }
      std::vector<std::uint8_t> want(n, 7), got(n, 7);
      const int end = static_cast<int>(n);
      simd::candidateMaskScalar(mag.data(), cells.data(), min_sq, from, end, want.data());
      const int c =
          simd::candidateMaskSse2(mag.data(), cells.data(), min_sq, from, end, got.data());
      ASSERT_EQ(end - c, (end - from) % 16);
      simd::candidateMaskScalar(mag.data(), cells.data(), min_sq, c, end, got.data());
      EXPECT_EQ(got, want) << n << " cells from " << from;
      for (size_t i = static_cast<size_t>(from); i < n; ++i) {
        candidates += want[i] == 1 ? 1 : 0;
        rejected += want[i] == 0 ? 1 : 0;
      }
    }
  }
  EXPECT_GT(candidates, 100);
  EXPECT_GT(rejected, 100);
#endif
}

}  // namespace
}  // namespace dlo
