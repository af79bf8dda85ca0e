// The SSE2 kernel of estimateSweepTimes()'s per-point loop: sweep_timing_scalar.cpp's
// operations in the same order, lane by lane.
#include "simd/sweep_timing_kernels.h"

#ifdef __SSE2__
#include <emmintrin.h>

namespace dlo::simd {

namespace {

constexpr float kTwoPiF = 6.28318530717958647692f;
constexpr float kPiF = 3.14159265358979323846f;

/// fastAtan2() of four lanes, the same operations in the same order.
__m128 fastAtan2(__m128 y, __m128 x) {
  const __m128 sign = _mm_set1_ps(-0.0f), zero = _mm_setzero_ps();
  const __m128 ax = _mm_andnot_ps(sign, x), ay = _mm_andnot_ps(sign, y);
  const __m128 hi = _mm_max_ps(ax, ay), lo = _mm_min_ps(ax, ay);
  const __m128 a = _mm_div_ps(lo, _mm_max_ps(hi, _mm_set1_ps(1e-30f)));
  const __m128 s = _mm_mul_ps(a, a);
  __m128 r = _mm_add_ps(_mm_mul_ps(_mm_set1_ps(-0.0117212f), s), _mm_set1_ps(0.05265332f));
  r = _mm_sub_ps(_mm_mul_ps(r, s), _mm_set1_ps(0.11643287f));
  r = _mm_add_ps(_mm_mul_ps(r, s), _mm_set1_ps(0.19354346f));
  r = _mm_sub_ps(_mm_mul_ps(r, s), _mm_set1_ps(0.33262347f));
  r = _mm_add_ps(_mm_mul_ps(r, s), _mm_set1_ps(0.99997726f));
  r = _mm_mul_ps(r, a);
  const auto select = [](__m128 mask, __m128 yes, __m128 no) {
    return _mm_or_ps(_mm_and_ps(mask, yes), _mm_andnot_ps(mask, no));
  };
  r = select(_mm_cmpgt_ps(ay, ax), _mm_sub_ps(_mm_set1_ps(1.57079632679f), r), r);
  r = select(_mm_cmplt_ps(x, zero), _mm_sub_ps(_mm_set1_ps(3.14159265359f), r), r);
  return select(_mm_cmplt_ps(y, zero), _mm_sub_ps(zero, r), r);
}

}  // namespace

size_t sweepTimesSse2(const SweepClock& c, const Eigen::Vector3f* points, size_t from, size_t n,
                      float* times) {
  const __m128 vdir = _mm_set1_ps(c.dir), vstart = _mm_set1_ps(c.start);
  const __m128 vscale = _mm_set1_ps(c.scale), voffset = _mm_set1_ps(c.offset);
  const __m128 two_pi = _mm_set1_ps(kTwoPiF), zero = _mm_setzero_ps();
  const __m128 vper_point = _mm_set1_ps(c.per_point), vpi = _mm_set1_ps(kPiF);
  const __m128 vminus_pi = _mm_set1_ps(-kPiF);
  size_t i = from;
  for (; i + 4 <= n; i += 4) {
    const Eigen::Vector3f* p = points + i;
    const __m128 x = _mm_setr_ps(p[0].x(), p[1].x(), p[2].x(), p[3].x());
    const __m128 y = _mm_setr_ps(p[0].y(), p[1].y(), p[2].y(), p[3].y());
    __m128 a = _mm_mul_ps(vdir, _mm_sub_ps(fastAtan2(y, x), vstart));
    a = _mm_add_ps(a, _mm_and_ps(_mm_cmplt_ps(a, zero), two_pi));
    a = _mm_sub_ps(a, _mm_and_ps(_mm_cmpge_ps(a, two_pi), two_pi));
    if (c.ordered) {
      // The point's index as a float, plus 1, 2, 3: the scalar code's float(i) for i below
      // 2^24 (a sweep has fewer points).
      const float k = static_cast<float>(i);
      const __m128 expected = _mm_mul_ps(_mm_setr_ps(k, k + 1.0f, k + 2.0f, k + 3.0f), vper_point);
      const __m128 ahead = _mm_sub_ps(a, expected);
      a = _mm_sub_ps(a, _mm_and_ps(_mm_cmpgt_ps(ahead, vpi), two_pi));
      a = _mm_add_ps(a, _mm_and_ps(_mm_cmplt_ps(ahead, vminus_pi), two_pi));
    }
    const __m128 t = _mm_add_ps(_mm_mul_ps(a, vscale), voffset);
    // t - t is 0 unless t is infinite or NaN (a non-finite point): those get the stamp's time.
    _mm_storeu_ps(times + i, _mm_and_ps(t, _mm_cmpeq_ps(_mm_sub_ps(t, t), zero)));
  }
  return i;
}

}  // namespace dlo::simd

#endif  // __SSE2__
