// The SSE2 kernel of the linearisation's sampling: sample_cells_scalar.cpp's arithmetic (with
// HeightSampler::sample()'s) in its order, four cells at a time.
#include "simd/sample_cells_kernels.h"

#ifdef __SSE2__
#include <emmintrin.h>

#include "simd/pose_sse2.h"

namespace dlo::simd {

namespace {

/// HeightSampler::sample() at four points (x, y lanes), each lane with sample()'s arithmetic in
/// its order: out[i] = (h, gx, gy, 1) where sample() would return true, and ok = 0 (the rest
/// unspecified) where it would return false. The bounds arithmetic runs two lanes at a time and
/// the interpolation without a branch, which lets a loop over many points overlap their reads.
void sample4(const HeightSampler& sampler, __m128 x, __m128 y, GradientCell out[4]) {
  const GridGeometry& geometry = sampler.geometry();
  const GradientCell* field = sampler.gradients().cells.data();
  const int cols = geometry.cols;
  // The loads below read the four cells from the lower-left one; lanes outside the grid read
  // cell 0's square instead, which exists only in a grid of at least 2 x 2 cells (a smaller
  // one has no lane inside).
  if (cols < 2 || geometry.rows < 2) {
    for (int i = 0; i < 4; ++i) out[i].ok = 0.0f;
    return;
  }
  const __m128d x0 = _mm_set1_pd(geometry.x_min), y0 = _mm_set1_pd(geometry.y_min);
  const __m128d inv = _mm_set1_pd(sampler.inverseResolution()), half = _mm_set1_pd(0.5);
  const __m128d u_end = _mm_set1_pd(cols - 1), v_end = _mm_set1_pd(geometry.rows - 1);
  const __m128d zero = _mm_setzero_pd();
  // The fractions of lanes 2 pair and 2 pair + 1 in the low half of each; joined in registers
  // (stored as floats and reloaded as a vector, they stalled store-to-load forwarding).
  __m128 fa[2], fb[2];
  int at[4];
  for (int pair = 0; pair < 2; ++pair) {
    // HeightSampler::lowerLeft() for lanes 2 pair and 2 pair + 1.
    const __m128 xs = pair == 0 ? x : _mm_movehl_ps(x, x);
    const __m128 ys = pair == 0 ? y : _mm_movehl_ps(y, y);
    const __m128d u = _mm_sub_pd(_mm_mul_pd(_mm_sub_pd(_mm_cvtps_pd(xs), x0), inv), half);
    const __m128d v = _mm_sub_pd(_mm_mul_pd(_mm_sub_pd(_mm_cvtps_pd(ys), y0), inv), half);
    const __m128d inside = _mm_and_pd(_mm_and_pd(_mm_cmpge_pd(u, zero), _mm_cmpge_pd(v, zero)),
                                      _mm_and_pd(_mm_cmplt_pd(u, u_end), _mm_cmplt_pd(v, v_end)));
    const int mask = _mm_movemask_pd(inside);
    // Truncation, as static_cast<int>; lanes outside may hold anything and are not used.
    const __m128i c = _mm_cvttpd_epi32(u), r = _mm_cvttpd_epi32(v);
    fa[pair] = _mm_cvtpd_ps(_mm_sub_pd(u, _mm_cvtepi32_pd(c)));
    fb[pair] = _mm_cvtpd_ps(_mm_sub_pd(v, _mm_cvtepi32_pd(r)));
    alignas(16) int ci[4], ri[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(ci), c);
    _mm_store_si128(reinterpret_cast<__m128i*>(ri), r);
    for (int j = 0; j < 2; ++j) {
      const bool in = (mask >> j) & 1;
      at[2 * pair + j] = in ? ri[j] * cols + ci[j] : -1;
    }
  }
  const __m128 one = _mm_set1_ps(1.0f);
  const __m128 av = _mm_movelh_ps(fa[0], fa[1]), bv = _mm_movelh_ps(fb[0], fb[1]);
  alignas(16) float w[4][4];  // w00, w01, w10, w11 of each lane
  _mm_store_ps(w[0], _mm_mul_ps(_mm_sub_ps(one, av), _mm_sub_ps(one, bv)));
  _mm_store_ps(w[1], _mm_mul_ps(av, _mm_sub_ps(one, bv)));
  _mm_store_ps(w[2], _mm_mul_ps(_mm_sub_ps(one, av), bv));
  _mm_store_ps(w[3], _mm_mul_ps(av, bv));
  for (int i = 0; i < 4; ++i) {
    const GradientCell* p0 = field + (at[i] < 0 ? 0 : at[i]);
    const GradientCell* p1 = p0 + cols;
    const __m128 c00 = _mm_loadu_ps(&p0[0].h), c01 = _mm_loadu_ps(&p0[1].h);
    const __m128 c10 = _mm_loadu_ps(&p1[0].h), c11 = _mm_loadu_ps(&p1[1].h);
    const __m128 s = _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(w[0][i]), c00),
                                                      _mm_mul_ps(_mm_set1_ps(w[1][i]), c01)),
                                           _mm_mul_ps(_mm_set1_ps(w[2][i]), c10)),
                                _mm_mul_ps(_mm_set1_ps(w[3][i]), c11));
    _mm_storeu_ps(&out[i].h, s);
    // sample()'s test on the product of the four flags (each 0 or 1).
    const float ok = p0[0].ok * p0[1].ok * p1[0].ok * p1[1].ok;
    out[i].ok = at[i] >= 0 && ok != 0.0f ? 1.0f : 0.0f;
  }
}

}  // namespace

size_t sampleCellsSse2(const HeightSampler& sampler, const SelectedCell* cells, size_t from,
                       size_t n, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                       CellSample* out) {
  const PoseSse2 pose(R, t);
  size_t k = from;
  for (; k + 4 <= n; k += 4) {
    const SelectedCell* c = cells + k;
    const __m128 x = _mm_setr_ps(c[0].x, c[1].x, c[2].x, c[3].x);
    const __m128 y = _mm_setr_ps(c[0].y, c[1].y, c[2].y, c[3].y);
    const __m128 h = _mm_setr_ps(c[0].h, c[1].h, c[2].h, c[3].h);
    __m128 q[3];
    for (int i = 0; i < 3; ++i) q[i] = pose.apply(i, x, y, h);
    GradientCell s[4];
    sample4(sampler, q[0], q[1], s);
    alignas(16) float qs[3][4];
    for (int i = 0; i < 3; ++i) _mm_store_ps(qs[i], q[i]);
    for (int j = 0; j < 4; ++j) {
      out[k + j].s = s[j];
      out[k + j].q = Eigen::Vector3f(qs[0][j], qs[1][j], qs[2][j]);
    }
  }
  return k;
}

}  // namespace dlo::simd

#endif  // __SSE2__
