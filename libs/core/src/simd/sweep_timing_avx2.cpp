// The AVX2 kernel of estimateSweepTimes()'s per-point loop, compiled for AVX2 on its own and
// called only where the processor has it (hasAvx2()): the SSE2 kernel's operations lane by
// lane, eight points at a time, in the same order (no fused multiply-add), so that all three
// give the same times bit for bit.
#include "simd/cpu_features.h"
#include "simd/sweep_timing_kernels.h"

#ifdef DLO_SIMD_AVX2_DISPATCH
#include <immintrin.h>

namespace dlo::simd {

namespace {

constexpr float kTwoPiF = 6.28318530717958647692f;
constexpr float kPiF = 3.14159265358979323846f;

__attribute__((target("avx2"))) __m256 select(__m256 mask, __m256 yes, __m256 no) {
  return _mm256_or_ps(_mm256_and_ps(mask, yes), _mm256_andnot_ps(mask, no));
}

/// fastAtan2() of eight lanes, the SSE2 kernel's operations in the same order.
__attribute__((target("avx2"))) __m256 fastAtan2(__m256 y, __m256 x) {
  const __m256 sign = _mm256_set1_ps(-0.0f), zero = _mm256_setzero_ps();
  const __m256 ax = _mm256_andnot_ps(sign, x), ay = _mm256_andnot_ps(sign, y);
  const __m256 hi = _mm256_max_ps(ax, ay), lo = _mm256_min_ps(ax, ay);
  const __m256 a = _mm256_div_ps(lo, _mm256_max_ps(hi, _mm256_set1_ps(1e-30f)));
  const __m256 s = _mm256_mul_ps(a, a);
  __m256 r =
      _mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(-0.0117212f), s), _mm256_set1_ps(0.05265332f));
  r = _mm256_sub_ps(_mm256_mul_ps(r, s), _mm256_set1_ps(0.11643287f));
  r = _mm256_add_ps(_mm256_mul_ps(r, s), _mm256_set1_ps(0.19354346f));
  r = _mm256_sub_ps(_mm256_mul_ps(r, s), _mm256_set1_ps(0.33262347f));
  r = _mm256_add_ps(_mm256_mul_ps(r, s), _mm256_set1_ps(0.99997726f));
  r = _mm256_mul_ps(r, a);
  r = select(_mm256_cmp_ps(ay, ax, _CMP_GT_OQ), _mm256_sub_ps(_mm256_set1_ps(1.57079632679f), r),
             r);
  r = select(_mm256_cmp_ps(x, zero, _CMP_LT_OQ), _mm256_sub_ps(_mm256_set1_ps(3.14159265359f), r),
             r);
  return select(_mm256_cmp_ps(y, zero, _CMP_LT_OQ), _mm256_sub_ps(zero, r), r);
}

}  // namespace

__attribute__((target("avx2"))) size_t sweepTimesAvx2(const SweepClock& c,
                                                      const Eigen::Vector3f* points, size_t from,
                                                      size_t n, float* times) {
  const __m256 vdir = _mm256_set1_ps(c.dir), vstart = _mm256_set1_ps(c.start);
  const __m256 vscale = _mm256_set1_ps(c.scale), voffset = _mm256_set1_ps(c.offset);
  const __m256 two_pi = _mm256_set1_ps(kTwoPiF), zero = _mm256_setzero_ps();
  const __m256 vper_point = _mm256_set1_ps(c.per_point), vpi = _mm256_set1_ps(kPiF);
  const __m256 vminus_pi = _mm256_set1_ps(-kPiF);
  size_t i = from;
  for (; i + 8 <= n; i += 8) {
    const Eigen::Vector3f* p = points + i;
    const __m256 x = _mm256_setr_ps(p[0].x(), p[1].x(), p[2].x(), p[3].x(), p[4].x(), p[5].x(),
                                    p[6].x(), p[7].x());
    const __m256 y = _mm256_setr_ps(p[0].y(), p[1].y(), p[2].y(), p[3].y(), p[4].y(), p[5].y(),
                                    p[6].y(), p[7].y());
    __m256 a = _mm256_mul_ps(vdir, _mm256_sub_ps(fastAtan2(y, x), vstart));
    a = _mm256_add_ps(a, _mm256_and_ps(_mm256_cmp_ps(a, zero, _CMP_LT_OQ), two_pi));
    a = _mm256_sub_ps(a, _mm256_and_ps(_mm256_cmp_ps(a, two_pi, _CMP_GE_OQ), two_pi));
    if (c.ordered) {
      // The point's index as a float, plus 1 ... 7: the scalar code's float(i) for i below
      // 2^24 (a sweep has fewer points).
      const float k = static_cast<float>(i);
      const __m256 expected = _mm256_mul_ps(
          _mm256_setr_ps(k, k + 1.0f, k + 2.0f, k + 3.0f, k + 4.0f, k + 5.0f, k + 6.0f, k + 7.0f),
          vper_point);
      const __m256 ahead = _mm256_sub_ps(a, expected);
      a = _mm256_sub_ps(a, _mm256_and_ps(_mm256_cmp_ps(ahead, vpi, _CMP_GT_OQ), two_pi));
      a = _mm256_add_ps(a, _mm256_and_ps(_mm256_cmp_ps(ahead, vminus_pi, _CMP_LT_OQ), two_pi));
    }
    const __m256 t = _mm256_add_ps(_mm256_mul_ps(a, vscale), voffset);
    // t - t is 0 unless t is infinite or NaN (a non-finite point): those get the stamp's time.
    _mm256_storeu_ps(times + i,
                     _mm256_and_ps(t, _mm256_cmp_ps(_mm256_sub_ps(t, t), zero, _CMP_EQ_OQ)));
  }
  return i;
}

}  // namespace dlo::simd

#endif  // DLO_SIMD_AVX2_DISPATCH
