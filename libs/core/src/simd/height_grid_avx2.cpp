// HeightGrid's AVX2 kernels, compiled for AVX2 function by function and called only where the
// processor has it (hasAvx2(); the build targets plain x86-64). Each does the SSE2 kernel's
// operations lane by lane, in the same order (no fused multiply-add), so that all three give
// the same cells.
#include "simd/height_grid_kernels.h"

#ifdef DLO_SIMD_AVX2_DISPATCH
#include <immintrin.h>

namespace dlo::simd {

namespace {

/// Four floats at `low` and four at `high` as the two halves of one 256-bit vector.
__attribute__((target("avx2"))) __m256 loadHalves(const float* low, const float* high) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(low)), _mm_loadu_ps(high), 1);
}

/// The pose broadcast into 256-bit vectors.
struct Pose8 {
  __attribute__((target("avx2"))) explicit Pose8(const RowMajorPose& m) {
    for (int i = 0; i < 12; ++i) r[i] = _mm256_set1_ps(m.m[i]);
  }
  __m256 r[12];
};

/// The discard cells of lanes 0..7 of groups of eight that start at `from` plus a multiple of 8.
__attribute__((target("avx2"))) __m256i discardLanes(const CellMapping& c, size_t from) {
  int lane[8];
  for (int j = 0; j < 8; ++j) lane[j] = c.discard + static_cast<int>((from + j) % kDiscardCells);
  return _mm256_setr_epi32(lane[0], lane[1], lane[2], lane[3], lane[4], lane[5], lane[6], lane[7]);
}

/// mapPoint()'s operations for eight points, in the same order.
__attribute__((target("avx2"))) void cells8(const CellMapping& c, const Pose8& pose,
                                            __m256i discard, __m256 px, __m256 py, __m256 pz,
                                            int* idx, float* z, float* fu, float* fv) {
  const __m256* r = pose.r;
  // Each row of the pose summed left to right, as RowMajorPose::apply().
  const __m256 x =
      _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(r[0], px), _mm256_mul_ps(r[1], py)),
                                  _mm256_mul_ps(r[2], pz)),
                    r[3]);
  const __m256 y =
      _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(r[4], px), _mm256_mul_ps(r[5], py)),
                                  _mm256_mul_ps(r[6], pz)),
                    r[7]);
  const __m256 h =
      _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(r[8], px), _mm256_mul_ps(r[9], py)),
                                  _mm256_mul_ps(r[10], pz)),
                    r[11]);
  const __m256 x0 = _mm256_set1_ps(c.x0), y0 = _mm256_set1_ps(c.y0),
               inv = _mm256_set1_ps(c.inv_res);
  const __m256 zero = _mm256_setzero_ps(), cols_f = _mm256_set1_ps(c.cols),
               rows_f = _mm256_set1_ps(c.rows), zlo = _mm256_set1_ps(c.zlo),
               zhi = _mm256_set1_ps(c.zhi);
  const __m256i cols_i = _mm256_set1_epi32(c.grid_cols);
  const __m256 u = _mm256_mul_ps(_mm256_sub_ps(x, x0), inv);
  const __m256 v = _mm256_mul_ps(_mm256_sub_ps(y, y0), inv);
  // Ordered compares: false for NaN.
  const __m256 inside = _mm256_and_ps(
      _mm256_and_ps(
          _mm256_and_ps(_mm256_cmp_ps(u, zero, _CMP_GE_OQ), _mm256_cmp_ps(u, cols_f, _CMP_LT_OQ)),
          _mm256_and_ps(_mm256_cmp_ps(v, zero, _CMP_GE_OQ), _mm256_cmp_ps(v, rows_f, _CMP_LT_OQ))),
      _mm256_and_ps(_mm256_cmp_ps(h, zlo, _CMP_GE_OQ), _mm256_cmp_ps(h, zhi, _CMP_LE_OQ)));
  const __m256i col = _mm256_cvttps_epi32(_mm256_and_ps(inside, u));
  const __m256i rr = _mm256_cvttps_epi32(_mm256_and_ps(inside, v));
  const __m256i cell = _mm256_add_epi32(_mm256_mullo_epi32(rr, cols_i), col);
  const __m256i in = _mm256_castps_si256(inside);
  _mm256_storeu_si256(
      reinterpret_cast<__m256i*>(idx),
      _mm256_or_si256(_mm256_and_si256(in, cell), _mm256_andnot_si256(in, discard)));
  _mm256_storeu_ps(z, h);
  if (fu != nullptr) {
    _mm256_storeu_ps(fu, _mm256_sub_ps(u, _mm256_cvtepi32_ps(col)));
    _mm256_storeu_ps(fv, _mm256_sub_ps(v, _mm256_cvtepi32_ps(rr)));
  }
}

}  // namespace

// 256-bit shuffles work within 128-bit halves: each half deinterleaves four points exactly as
// the SSE2 kernel does.
__attribute__((target("avx2"))) size_t mapPointsAvx2(const CellMapping& cells,
                                                     const Eigen::Vector3f* p, size_t from,
                                                     size_t n, const RowMajorPose& m,
                                                     int* __restrict__ idx, float* __restrict__ z,
                                                     CellFractions f) {
  // A cast, not p->data(): with no points p may be null.
  const float* __restrict__ q = reinterpret_cast<const float*>(p);
  const Pose8 pose(m);
  const __m256i discard = discardLanes(cells, from);
  size_t k = from;
  for (; k + 8 <= n; k += 8) {
    _mm_prefetch(reinterpret_cast<const char*>(q + 3 * k + 768), _MM_HINT_T0);
    const float* at = q + 3 * k;
    const __m256 a = loadHalves(at, at + 12);
    const __m256 b = loadHalves(at + 4, at + 16);
    const __m256 c = loadHalves(at + 8, at + 20);
    const __m256 bc = _mm256_shuffle_ps(b, c, _MM_SHUFFLE(1, 1, 2, 2));
    const __m256 px = _mm256_shuffle_ps(a, bc, _MM_SHUFFLE(2, 0, 3, 0));
    const __m256 py = _mm256_shuffle_ps(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 1, 1)),
                                        _mm256_shuffle_ps(b, c, _MM_SHUFFLE(2, 2, 3, 3)),
                                        _MM_SHUFFLE(2, 0, 2, 0));
    const __m256 pz = _mm256_shuffle_ps(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(1, 1, 2, 2)),
                                        _mm256_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 0, 0)),
                                        _MM_SHUFFLE(2, 0, 2, 0));
    cells8(cells, pose, discard, px, py, pz, idx + k, z + k, f.u ? f.u + k : nullptr,
           f.v ? f.v + k : nullptr);
  }
  return k;
}

__attribute__((target("avx2"))) size_t mapWeightedAvx2(
    const CellMapping& cells, const WeightedPoint* p, size_t from, size_t n, const RowMajorPose& m,
    int* __restrict__ idx, float* __restrict__ z, std::uint32_t* __restrict__ w, CellFractions f) {
  // A cast, not p->p.data(): with no points p may be null.
  const float* __restrict__ q = reinterpret_cast<const float*>(p);
  const Pose8 pose(m);
  const __m256i discard = discardLanes(cells, from);
  size_t k = from;
  for (; k + 8 <= n; k += 8) {
    _mm_prefetch(reinterpret_cast<const char*>(q + 4 * k + 1024), _MM_HINT_T0);
    const float* at = q + 4 * k;
    // Rows k..k+3 in the low halves, k+4..k+7 in the high ones; then _MM_TRANSPOSE4_PS in
    // each half.
    const __m256 r0 = loadHalves(at, at + 16);
    const __m256 r1 = loadHalves(at + 4, at + 20);
    const __m256 r2 = loadHalves(at + 8, at + 24);
    const __m256 r3 = loadHalves(at + 12, at + 28);
    const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpacklo_ps(r2, r3);
    const __m256 t2 = _mm256_unpackhi_ps(r0, r1), t3 = _mm256_unpackhi_ps(r2, r3);
    const __m256 px = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 py = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 2, 3, 2));
    const __m256 pz = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 pn = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(3, 2, 3, 2));
    cells8(cells, pose, discard, px, py, pz, idx + k, z + k, f.u ? f.u + k : nullptr,
           f.v ? f.v + k : nullptr);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(w + k), _mm256_castps_si256(pn));
  }
  return k;
}

}  // namespace dlo::simd

#endif  // DLO_SIMD_AVX2_DISPATCH
