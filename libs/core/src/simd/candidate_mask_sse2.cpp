// The SSE2 kernel of selectHighGradientCells()'s candidate test: candidate_mask_scalar.cpp's
// test, sixteen cells at a time.
#include "simd/candidate_mask_kernels.h"

#ifdef __SSE2__
#include <emmintrin.h>

namespace dlo::simd {

int candidateMaskSse2(const float* mag, const std::uint8_t* measured, float min_sq, int from, int n,
                      std::uint8_t* mask) {
  const __m128 threshold = _mm_set1_ps(min_sq);
  int c = from;
  for (; c + 16 <= n; c += 16) {
    const __m128i v0 = _mm_castps_si128(_mm_cmpge_ps(_mm_loadu_ps(mag + c), threshold));
    const __m128i v1 = _mm_castps_si128(_mm_cmpge_ps(_mm_loadu_ps(mag + c + 4), threshold));
    const __m128i v2 = _mm_castps_si128(_mm_cmpge_ps(_mm_loadu_ps(mag + c + 8), threshold));
    const __m128i v3 = _mm_castps_si128(_mm_cmpge_ps(_mm_loadu_ps(mag + c + 12), threshold));
    // 32-bit all-ones / zeros, narrowed to bytes with signed saturation (-1 stays -1).
    const __m128i above = _mm_packs_epi16(_mm_packs_epi32(v0, v1), _mm_packs_epi32(v2, v3));
    const __m128i cells_measured = _mm_loadu_si128(reinterpret_cast<const __m128i*>(measured + c));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(mask + c), _mm_and_si128(above, cells_measured));
  }
  return c;
}

}  // namespace dlo::simd

#endif  // __SSE2__
