// The SSE2 kernel of voxelise()'s keys: voxel_keys_scalar.cpp's voxelAxis() operation for
// operation, four values at a time.
#include "simd/voxel_keys_kernels.h"

#ifdef __SSE2__
#include <emmintrin.h>

namespace dlo::simd {

namespace {

/// voxelAxis() of four values. SSE2 has no floor: truncation, minus one where it rounded up
/// (negative non-integers).
__m128i voxelAxis4(__m128 v, __m128 inv_voxel) {
  const __m128 t = _mm_max_ps(_mm_min_ps(_mm_mul_ps(v, inv_voxel), _mm_set1_ps(2.0f * kAxisOffset)),
                              _mm_set1_ps(-kAxisOffset - 1.0f));
  const __m128i trunc = _mm_cvttps_epi32(t);
  // The comparison's all-ones lanes are -1.
  const __m128i floor =
      _mm_add_epi32(trunc, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(trunc), t)));
  const __m128i i = _mm_add_epi32(floor, _mm_set1_epi32(kAxisOffset));
  const __m128i hi = _mm_set1_epi32(kAxisMax);
  const __m128i non_negative = _mm_andnot_si128(_mm_cmplt_epi32(i, _mm_setzero_si128()), i);
  const __m128i above = _mm_cmpgt_epi32(non_negative, hi);
  return _mm_or_si128(_mm_andnot_si128(above, non_negative), _mm_and_si128(above, hi));
}

}  // namespace

size_t voxelKeysSse2(const float* x, const float* y, const float* z, size_t from, size_t n,
                     float inv_voxel, std::uint64_t* keys) {
  const __m128 inv = _mm_set1_ps(inv_voxel);
  alignas(16) std::int32_t ix[4], iy[4], iz[4];
  size_t k = from;
  for (; k + 4 <= n; k += 4) {
    _mm_store_si128(reinterpret_cast<__m128i*>(ix), voxelAxis4(_mm_loadu_ps(x + k), inv));
    _mm_store_si128(reinterpret_cast<__m128i*>(iy), voxelAxis4(_mm_loadu_ps(y + k), inv));
    _mm_store_si128(reinterpret_cast<__m128i*>(iz), voxelAxis4(_mm_loadu_ps(z + k), inv));
    for (int j = 0; j < 4; ++j) keys[k + j] = voxelKey(ix[j], iy[j], iz[j]);
  }
  return k;
}

}  // namespace dlo::simd

#endif  // __SSE2__
