// SweepMotion's SSE2 kernels: deskew_scalar.cpp's operations, four lanes at a time.
#include "simd/deskew_kernels.h"

#ifdef __SSE2__
#include <emmintrin.h>

#include <algorithm>

namespace dlo::simd {

size_t widenTimeRangeSse2(const float* t, size_t from, size_t n, float& lo, float& hi) {
  if (n < from + 4) return from;
  // MINPS and MAXPS return their second operand when either is NaN: a NaN time is skipped.
  __m128 vlo = _mm_set1_ps(lo), vhi = _mm_set1_ps(hi);
  size_t k = from;
  for (; k + 4 <= n; k += 4) {
    const __m128 v = _mm_loadu_ps(t + k);
    vlo = _mm_min_ps(v, vlo);
    vhi = _mm_max_ps(v, vhi);
  }
  float l[4], h[4];
  _mm_storeu_ps(l, vlo);
  _mm_storeu_ps(h, vhi);
  for (int i = 0; i < 4; ++i) {
    lo = std::min(lo, l[i]);
    hi = std::max(hi, h[i]);
  }
  return k;
}

size_t timeBinsSse2(const TimeBins& b, const float* t, size_t from, size_t n, int* out) {
  // f lies in [0, bins] for the times the motion was tabulated over (a NaN time becomes 0, as
  // the clamp in the scalar code makes it).
  const __m128 lo = _mm_set1_ps(b.lo), span = _mm_set1_ps(b.span);
  const __m128 top = _mm_set1_ps(static_cast<float>(b.bins));
  const __m128 zero = _mm_setzero_ps(), half = _mm_set1_ps(0.5f);
  size_t k = from;
  for (; k + 4 <= n; k += 4) {
    __m128 f = _mm_mul_ps(_mm_div_ps(_mm_sub_ps(_mm_loadu_ps(t + k), lo), span), top);
    f = _mm_min_ps(_mm_max_ps(f, zero), top);  // max(NaN, 0) is 0
    const __m128i i = _mm_cvttps_epi32(f);
    // Rounded half up: all ones (-1) where the fraction is at least 1/2.
    const __m128i up = _mm_castps_si128(_mm_cmpge_ps(_mm_sub_ps(f, _mm_cvtepi32_ps(i)), half));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), _mm_sub_epi32(i, up));
  }
  return k;
}

}  // namespace dlo::simd

#endif  // __SSE2__
