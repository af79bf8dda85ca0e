// SweepMotion's kernels (libs/core/src/simd/deskew_sse2.cpp) against their scalar references on
// fixed-seed random sweep times.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "dlo/core/deskew.h"
#include "kernel_test_util.h"
#include "simd/deskew_kernels.h"

namespace dlo {
namespace {

/// Times of a 10 Hz sweep around its stamp, and runs of equal times (a firing).
std::vector<float> someTimes(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> t(-0.05f, 0.05f);
  std::vector<float> times(n);
  for (size_t k = 0; k < n; ++k) times[k] = k % 5 == 4 ? times[k - 1] : t(rng);
  return times;
}

// The range: the same smallest and largest values, compared with == (a -0 and a +0 among the
// extremes may come out with the other sign: lanes keep the first zero they met, the scan the
// first of all; they are equal and give the same bins). NaN times are skipped by both.
TEST(DeskewKernels, TimeRangeSse2HasTheScalarExtremes) {
#ifndef __SSE2__
  GTEST_SKIP() << "no SSE2 kernel on this processor";
#else
  std::mt19937 rng = test::seeded(41);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t n : test::edgeLengths()) {
    if (n == 0) continue;  // SweepMotion starts from the first time
    for (int trial = 0; trial < 8; ++trial) {
      std::vector<float> t = someTimes(n, rng);
      if (n > 2) t[n / 2] = nan;
      if (trial % 2 == 1 && n > 1) t[n - 1] = -1.0f;  // the extreme in the scalar tail
      float want_lo = t[0], want_hi = t[0], got_lo = t[0], got_hi = t[0];
      simd::widenTimeRangeScalar(t.data(), 0, n, want_lo, want_hi);
      const size_t k = simd::widenTimeRangeSse2(t.data(), 0, n, got_lo, got_hi);
      ASSERT_EQ(k, n - n % 4);
      simd::widenTimeRangeScalar(t.data(), k, n, got_lo, got_hi);
      EXPECT_EQ(got_lo, want_lo) << n << " times";
      EXPECT_EQ(got_hi, want_hi) << n << " times";
      EXPECT_FALSE(std::isnan(got_lo) || std::isnan(got_hi));
    }
  }
#endif
}

// The bins promise bit-identity: exact comparison. Times lie in the range the motion was
// tabulated over (as the callers' do), with no NaN: the scalar reference would convert NaN to
// int, which C++ leaves undefined.
TEST(DeskewKernels, TimeBinsSse2IsScalarExactly) {
#ifndef __SSE2__
  GTEST_SKIP() << "no SSE2 kernel on this processor";
#else
  std::mt19937 rng = test::seeded(42);
  int half_way = 0;
  for (size_t n : test::edgeLengths()) {
    for (int bins : {1, 7, 128}) {
      std::vector<float> t = someTimes(std::max<size_t>(n, 2), rng);
      const float lo = *std::min_element(t.begin(), t.end());
      const float hi = *std::max_element(t.begin(), t.end());
      const simd::TimeBins b{lo, std::max(hi - lo, 1e-9f), bins};
      // Times exactly half-way between bins, where rounding decides.
      for (size_t k = 0; k < t.size(); k += 3) {
        t[k] = lo + b.span * (static_cast<float>(k % bins) + 0.5f) / static_cast<float>(bins);
        half_way += 1;
      }
      std::vector<int> want(n, -7), got(n, -7);
      simd::timeBinsScalar(b, t.data(), 0, n, want.data());
      const size_t k = simd::timeBinsSse2(b, t.data(), 0, n, got.data());
      ASSERT_EQ(k, n - n % 4);
      simd::timeBinsScalar(b, t.data(), k, n, got.data());
      EXPECT_EQ(got, want) << n << " times, " << bins << " bins";
    }
  }
  EXPECT_GT(half_way, 100);
#endif
}

// timeBinsScalar() repeats SweepMotion::bin()'s arithmetic (bin() is inline in the public
// header): the two must agree, or the kernels would be checked against the wrong reference.
TEST(DeskewKernels, TimeBinsScalarIsSweepMotionBin) {
  std::mt19937 rng = test::seeded(43);
  const std::vector<float> t = someTimes(1001, rng);
  const SweepMotion motion(t, Vector6d::Zero(), 128);
  const float lo = *std::min_element(t.begin(), t.end());
  const float hi = *std::max_element(t.begin(), t.end());
  const simd::TimeBins b{lo, std::max(hi - lo, 1e-9f), 128};
  std::vector<int> bins(t.size()), via_bins(t.size());
  simd::timeBinsScalar(b, t.data(), 0, t.size(), bins.data());
  motion.bins(t.data(), t.size(), via_bins.data());
  for (size_t k = 0; k < t.size(); ++k) {
    EXPECT_EQ(bins[k], motion.bin(t[k])) << k;
    EXPECT_EQ(via_bins[k], motion.bin(t[k])) << k;
  }
}

}  // namespace
}  // namespace dlo
