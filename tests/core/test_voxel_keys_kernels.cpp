// voxelise()'s keys: the SSE2 kernel (libs/core/src/simd/voxel_keys_sse2.cpp) against its
// scalar reference on fixed-seed random coordinates. The kernel promises the same keys, so the
// comparison is exact.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "kernel_test_util.h"
#include "simd/voxel_keys_kernels.h"

namespace dlo {
namespace {

TEST(VoxelKeysKernels, Sse2IsScalarExactly) {
#ifndef __SSE2__
  GTEST_SKIP() << "no SSE2 kernel on this processor";
#else
  std::mt19937 rng = test::seeded(31);
  // Coordinates of a drive (hundreds of metres), near zero (the floor of small negatives),
  // whole multiples of the voxel, beyond the key's range (clamped) and NaN.
  std::uniform_real_distribution<float> far(-300.0f, 300.0f), near(-0.3f, 0.3f);
  std::uniform_int_distribution<int> kind(0, 9), step(-50, 50);
  const float inv_voxel = 1.0f / 0.1f;
  const float specials[] = {0.0f,
                            -0.0f,
                            -0.1f,
                            0.1f,
                            1e9f,
                            -1e9f,
                            std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity()};
  auto coordinate = [&]() {
    switch (kind(rng)) {
      case 0:
        return near(rng);
      case 1:
        return static_cast<float>(step(rng)) * 0.1f;
      case 2:
        return specials[static_cast<size_t>(step(rng) + 50) % std::size(specials)];
      default:
        return far(rng);
    }
  };
  int negative = 0;
  for (size_t n : test::edgeLengths()) {
    for (int trial = 0; trial < 8; ++trial) {
      std::vector<float> x(n), y(n), z(n);
      for (size_t k = 0; k < n; ++k) {
        x[k] = coordinate();
        y[k] = coordinate();
        z[k] = coordinate();
        negative += x[k] < 0.0f && x[k] * inv_voxel != std::floor(x[k] * inv_voxel) ? 1 : 0;
      }
      std::vector<std::uint64_t> want(n, 7), got(n, 7);
      simd::voxelKeysScalar(x.data(), y.data(), z.data(), 0, n, inv_voxel, want.data());
      const size_t k =
          simd::voxelKeysSse2(x.data(), y.data(), z.data(), 0, n, inv_voxel, got.data());
      ASSERT_EQ(k, n - n % 4);
      simd::voxelKeysScalar(x.data(), y.data(), z.data(), k, n, inv_voxel, got.data());
      EXPECT_EQ(got, want) << n << " points";
    }
  }
  EXPECT_GT(negative, 100) << "negative non-integers (where truncation is not the floor)";
#endif
}

}  // namespace
}  // namespace dlo
