// estimateSweepTimes()'s per-point loop: the SSE2 kernel (libs/core/src/simd/
// sweep_timing_sse2.cpp) against its scalar reference on fixed-seed random sweeps. The kernel
// promises the same times bit for bit (same operations in the same order), so the comparison
// is exact.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "kernel_test_util.h"
#include "simd/sweep_timing_kernels.h"

namespace dlo {
namespace {

using test::sameBits;

/// Points all round the sensor, some on the axes and at the origin (atan2's octant edges), a
/// few infinite ones and one NaN point. Not a point with one NaN coordinate: the readers drop
/// every non-finite point before the odometry (observation_to_scan.cpp, point_conversion.cpp,
/// kitti_scan_source.cpp), and there the kernel and the reference differ (see
/// simd/sweep_timing_kernels.h).
PointCloud someSweep(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> xy(-60.0f, 60.0f), z(-3.0f, 3.0f);
  PointCloud p(n);
  for (size_t k = 0; k < n; ++k) p[k] = Eigen::Vector3f(xy(rng), xy(rng), z(rng));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const Eigen::Vector3f special[] = {{0, 0, 0},     {5, 0, 0},   {-5, 0, 0},  {0, 5, 0},
                                     {0, -5, 0},    {3, 3, 0},   {-3, 3, 0},  {-3, -0.0f, 0},
                                     {nan, nan, 0}, {1, inf, 0}, {-inf, 1, 0}};
  for (size_t k = 0; k < n && k < std::size(special); ++k) p[(k * 7) % n] = special[k];
  return p;
}

/// Checks a kernel of `lanes` points at a time against the scalar reference, bit for bit.
template <typename Kernel>
void expectScalarBitForBit(Kernel kernel, size_t lanes) {
  std::mt19937 rng = test::seeded(21);
  std::vector<size_t> lengths = test::edgeLengths();
  lengths.push_back(4093);
  int wrapped = 0;
  for (size_t n : lengths) {
    const PointCloud p = someSweep(n, rng);
    // Both spin directions, with and without the storage order, starts all round.
    for (int variant = 0; variant < 4; ++variant) {
      const bool ordered = variant % 2 == 1;
      const float dir = variant < 2 ? 1.0f : -1.0f;
      const float start = std::uniform_real_distribution<float>(-3.14f, 3.14f)(rng);
      const simd::SweepClock clock{start,
                                   dir,
                                   0.1f / 6.2831853f,
                                   -0.05f,
                                   ordered && n > 0 ? 6.2831853f / static_cast<float>(n) : 0.0f,
                                   ordered};
      std::vector<float> want(n, -7.0f), got(n, -7.0f);
      simd::sweepTimesScalar(clock, p.data(), 0, n, want.data());
      const size_t k = kernel(clock, p.data(), 0, n, got.data());
      ASSERT_EQ(k, n - n % lanes);
      simd::sweepTimesScalar(clock, p.data(), k, n, got.data());
      for (size_t i = 0; i < n; ++i) {
        EXPECT_TRUE(sameBits(got[i], want[i]))
            << "point " << i << " of " << n << ": " << got[i] << " vs " << want[i];
        wrapped += want[i] > 0.045f ? 1 : 0;
      }
    }
  }
  EXPECT_GT(wrapped, 100) << "times from all over the sweep were compared";
}

TEST(SweepTimingKernels, Sse2IsScalarBitForBit) {
#ifndef __SSE2__
  GTEST_SKIP() << "no SSE2 kernel on this processor";
#else
  expectScalarBitForBit(simd::sweepTimesSse2, 4);
#endif
}

TEST(SweepTimingKernels, Avx2IsScalarBitForBit) {
#ifndef DLO_SIMD_AVX2_DISPATCH
  GTEST_SKIP() << "no AVX2 kernel in this build";
#else
  if (!simd::hasAvx2()) GTEST_SKIP() << "this processor has no AVX2";
  expectScalarBitForBit(simd::sweepTimesAvx2, 8);
#endif
}

TEST(SweepTimingKernels, FastAtan2IsWithinItsStatedError) {
  // The reference itself: within 2e-5 rad of std::atan2 all round.
  std::mt19937 rng = test::seeded(22);
  std::uniform_real_distribution<float> xy(-10.0f, 10.0f);
  for (int k = 0; k < 100000; ++k) {
    const float x = xy(rng), y = xy(rng);
    EXPECT_NEAR(simd::fastAtan2(y, x), std::atan2(y, x), 2e-5) << x << ", " << y;
  }
}

}  // namespace
}  // namespace dlo
