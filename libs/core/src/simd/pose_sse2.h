/// \file pose_sse2.h
/// \brief A pose (R, t) broadcast to SSE2 lanes, applied to four points as Eigen applies it to
/// one: the registration kernels (sample_cells_sse2.cpp, place_cells_sse2.cpp) share it so that
/// their results stay bit for bit those of their scalar references (internal to dlo_core).
#pragma once

#ifdef __SSE2__
#include <emmintrin.h>

#include <Eigen/Core>

namespace dlo::simd {

struct PoseSse2 {
  __m128 r[3][3];  ///< r[i][j] = R(i, j) in every lane
  __m128 t[3];

  PoseSse2(const Eigen::Matrix3f& R, const Eigen::Vector3f& tv) {
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r[i][j] = _mm_set1_ps(R(i, j));
      t[i] = _mm_set1_ps(tv(i));
    }
  }

  /// Row i of R p + t for four points p = (x, y, z): summed as Eigen's fixed-size product sums
  /// three terms, r0 x + (r1 y + r2 z), then + t.
  __m128 apply(int i, __m128 x, __m128 y, __m128 z) const {
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(r[i][0], x),
                                 _mm_add_ps(_mm_mul_ps(r[i][1], y), _mm_mul_ps(r[i][2], z))),
                      t[i]);
  }

  /// Row i of R^T p, summed the same way: R(0, i) x + (R(1, i) y + R(2, i) z).
  __m128 applyTransposed(int i, __m128 x, __m128 y, __m128 z) const {
    return _mm_add_ps(_mm_mul_ps(r[0][i], x),
                      _mm_add_ps(_mm_mul_ps(r[1][i], y), _mm_mul_ps(r[2][i], z)));
  }
};

}  // namespace dlo::simd

#endif  // __SSE2__
