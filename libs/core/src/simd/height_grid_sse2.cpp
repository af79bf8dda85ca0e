// HeightGrid's SSE2 kernels (SSE2 is part of x86-64): each follows its scalar reference in
// height_grid_scalar.cpp operation for operation, lane by lane.
#include "simd/height_grid_kernels.h"

#ifdef __SSE2__
#include <emmintrin.h>

namespace dlo::simd {

namespace {

/// The pose broadcast into vectors.
struct Pose4 {
  explicit Pose4(const RowMajorPose& m) {
    for (int i = 0; i < 12; ++i) r[i] = _mm_set1_ps(m.m[i]);
  }
  __m128 r[12];
};

/// The discard cells of lanes 0..3 of groups of four that start at `from` plus a multiple of 4.
__m128i discardLanes(const CellMapping& c, size_t from) {
  int lane[4];
  for (int j = 0; j < 4; ++j) lane[j] = c.discard + static_cast<int>((from + j) % kDiscardCells);
  return _mm_setr_epi32(lane[0], lane[1], lane[2], lane[3]);
}

/// mapPoint()'s operations in the same order for four points, so both give the same cells.
void cells4(const CellMapping& c, const Pose4& m, __m128i discard4, __m128 px, __m128 py, __m128 pz,
            int* idx, float* z, float* fu, float* fv) {
  const auto row = [&](int i) {
    return _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(m.r[i], px), _mm_mul_ps(m.r[i + 1], py)),
                                 _mm_mul_ps(m.r[i + 2], pz)),
                      m.r[i + 3]);
  };
  const __m128 x = row(0), y = row(4), h = row(8);
  const __m128 u = _mm_mul_ps(_mm_sub_ps(x, _mm_set1_ps(c.x0)), _mm_set1_ps(c.inv_res));
  const __m128 v = _mm_mul_ps(_mm_sub_ps(y, _mm_set1_ps(c.y0)), _mm_set1_ps(c.inv_res));
  const __m128 zero = _mm_setzero_ps();
  // Ordered compares: false for NaN.
  const __m128 inside = _mm_and_ps(
      _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(u, zero), _mm_cmplt_ps(u, _mm_set1_ps(c.cols))),
                 _mm_and_ps(_mm_cmpge_ps(v, zero), _mm_cmplt_ps(v, _mm_set1_ps(c.rows)))),
      _mm_and_ps(_mm_cmpge_ps(h, _mm_set1_ps(c.zlo)), _mm_cmple_ps(h, _mm_set1_ps(c.zhi))));
  const __m128i col = _mm_cvttps_epi32(_mm_and_ps(inside, u));
  const __m128i r = _mm_cvttps_epi32(_mm_and_ps(inside, v));
  // r * grid_cols in 32 bits: lanes 0 and 2, then 1 and 3.
  const __m128i cols = _mm_set1_epi32(c.grid_cols);
  const __m128i even = _mm_mul_epu32(r, cols);
  const __m128i odd = _mm_mul_epu32(_mm_srli_epi64(r, 32), cols);
  const __m128i prod = _mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                                          _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0)));
  const __m128i cell = _mm_add_epi32(prod, col);
  const __m128i in = _mm_castps_si128(inside);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(idx),
                   _mm_or_si128(_mm_and_si128(in, cell), _mm_andnot_si128(in, discard4)));
  _mm_storeu_ps(z, h);
  if (fu != nullptr) {
    _mm_storeu_ps(fu, _mm_sub_ps(u, _mm_cvtepi32_ps(col)));
    _mm_storeu_ps(fv, _mm_sub_ps(v, _mm_cvtepi32_ps(r)));
  }
}

}  // namespace

size_t mapPointsSse2(const CellMapping& cells, const Eigen::Vector3f* p, size_t from, size_t n,
                     const RowMajorPose& m, int* __restrict__ idx, float* __restrict__ z,
                     CellFractions f) {
  // A cast, not p->data(): with no points p may be null.
  const float* __restrict__ q = reinterpret_cast<const float*>(p);
  const Pose4 pose(m);
  const __m128i discard4 = discardLanes(cells, from);
  size_t k = from;
  for (; k + 4 <= n; k += 4) {
    // The sweep is read once, front to back; fetched a batch ahead, its loads stopped
    // stalling the loop (rasterisation 0.54 -> 0.42 ms per HDL-64 sweep).
    _mm_prefetch(reinterpret_cast<const char*>(q + 3 * k + 768), _MM_HINT_T0);
    // a = x0 y0 z0 x1, b = y1 z1 x2 y2, c = z2 x3 y3 z3: deinterleave into x, y, z.
    const __m128 a = _mm_loadu_ps(q + 3 * k);
    const __m128 b = _mm_loadu_ps(q + 3 * k + 4);
    const __m128 c = _mm_loadu_ps(q + 3 * k + 8);
    const __m128 bc = _mm_shuffle_ps(b, c, _MM_SHUFFLE(1, 1, 2, 2));
    const __m128 px = _mm_shuffle_ps(a, bc, _MM_SHUFFLE(2, 0, 3, 0));
    const __m128 py =
        _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 1, 1)),
                       _mm_shuffle_ps(b, c, _MM_SHUFFLE(2, 2, 3, 3)), _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 pz =
        _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(1, 1, 2, 2)),
                       _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 0, 0)), _MM_SHUFFLE(2, 0, 2, 0));
    cells4(cells, pose, discard4, px, py, pz, idx + k, z + k, f.u ? f.u + k : nullptr,
           f.v ? f.v + k : nullptr);
  }
  return k;
}

size_t mapWeightedSse2(const CellMapping& cells, const WeightedPoint* p, size_t from, size_t n,
                       const RowMajorPose& m, int* __restrict__ idx, float* __restrict__ z,
                       std::uint32_t* __restrict__ w, CellFractions f) {
  static_assert(sizeof(WeightedPoint) == 4 * sizeof(float), "x y z n, packed");
  // A cast, not p->p.data(): with no points p may be null.
  const float* __restrict__ q = reinterpret_cast<const float*>(p);
  const Pose4 pose(m);
  const __m128i discard4 = discardLanes(cells, from);
  size_t k = from;
  for (; k + 4 <= n; k += 4) {
    _mm_prefetch(reinterpret_cast<const char*>(q + 4 * k + 1024), _MM_HINT_T0);
    // Four rows of x y z n, transposed into columns.
    __m128 px = _mm_loadu_ps(q + 4 * k);
    __m128 py = _mm_loadu_ps(q + 4 * k + 4);
    __m128 pz = _mm_loadu_ps(q + 4 * k + 8);
    __m128 pn = _mm_loadu_ps(q + 4 * k + 12);
    _MM_TRANSPOSE4_PS(px, py, pz, pn);
    cells4(cells, pose, discard4, px, py, pz, idx + k, z + k, f.u ? f.u + k : nullptr,
           f.v ? f.v + k : nullptr);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(w + k), _mm_castps_si128(pn));
  }
  return k;
}

size_t binRunEndSse2(const int* bin, size_t k, size_t from, size_t n) {
  const __m128i same = _mm_set1_epi32(bin[k]);
  size_t end = from;
  while (end + 4 <= n &&
         _mm_movemask_epi8(_mm_cmpeq_epi32(
             _mm_loadu_si128(reinterpret_cast<const __m128i*>(bin + end)), same)) == 0xFFFF) {
    end += 4;
  }
  return end;
}

int finaliseCellsSse2(const CellSums& cells, int from, int& valid_cells) {
  const std::int32_t* __restrict__ cnt = cells.count;
  const float* __restrict__ sum = cells.sum;
  float* __restrict__ height = cells.height;
  std::uint8_t* __restrict__ valid = cells.valid;
  const PoolRow* pool = cells.pool;
  // Sixteen cells at a time. Measured cells are a few percent of a grid, clustered: a group
  // without one is written as zeros without dividing (the divisions over the whole grid were
  // most of this function). Invalid lanes divide by 1 and are masked; "+ 0" turns -0 into 0.
  const __m128i at_least = _mm_set1_epi32(cells.need - 1);  // cnt > need - 1
  const __m128i one = _mm_set1_epi32(1);
  const __m128 zero = _mm_setzero_ps();
  int i = from;
  for (; i + 16 <= cells.n; i += 16) {
    __m128i c[4], ok[4];
    for (int g = 0; g < 4; ++g) {
      c[g] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cnt + i + 4 * g));
      ok[g] = _mm_cmpgt_epi32(c[g], at_least);  // all ones if valid
    }
    if (pool != nullptr) {
      // Pairs of cells, as even + odd lanes; a group without points adds nothing (the coarse
      // sums start at +0 and never become -0, so adding +0 would not change them either).
      const __m128i any = _mm_or_si128(_mm_or_si128(c[0], c[1]), _mm_or_si128(c[2], c[3]));
      if (_mm_movemask_epi8(_mm_cmpeq_epi32(any, _mm_setzero_si128())) != 0xFFFF) {
        for (int h = 0; h < 2; ++h) {
          const int j = i / 2 + 4 * h;
          const __m128 a = _mm_castsi128_ps(c[2 * h]), b = _mm_castsi128_ps(c[2 * h + 1]);
          const __m128i pairs =
              _mm_add_epi32(_mm_castps_si128(_mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0))),
                            _mm_castps_si128(_mm_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1))));
          __m128i* gc = reinterpret_cast<__m128i*>(pool->count + j);
          _mm_storeu_si128(gc, _mm_add_epi32(_mm_loadu_si128(gc), pairs));
          const __m128 s0 = _mm_loadu_ps(sum + i + 8 * h), s1 = _mm_loadu_ps(sum + i + 8 * h + 4);
          const __m128 sums = _mm_add_ps(_mm_shuffle_ps(s0, s1, _MM_SHUFFLE(2, 0, 2, 0)),
                                         _mm_shuffle_ps(s0, s1, _MM_SHUFFLE(3, 1, 3, 1)));
          _mm_storeu_ps(pool->sum + j, _mm_add_ps(_mm_loadu_ps(pool->sum + j), sums));
        }
      }
    }
    // -1 / 0 per cell, narrowed to bytes with signed saturation.
    const __m128i flags =
        _mm_packs_epi16(_mm_packs_epi32(ok[0], ok[1]), _mm_packs_epi32(ok[2], ok[3]));
    const int bits = _mm_movemask_epi8(flags);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(valid + i), _mm_and_si128(flags, _mm_set1_epi8(1)));
    if (bits == 0) {
      for (int g = 0; g < 4; ++g) _mm_storeu_ps(height + i + 4 * g, zero);
      continue;
    }
    valid_cells += __builtin_popcount(static_cast<unsigned>(bits));
    for (int g = 0; g < 4; ++g) {
      const __m128 divisor =
          _mm_cvtepi32_ps(_mm_or_si128(_mm_and_si128(c[g], ok[g]), _mm_andnot_si128(ok[g], one)));
      const __m128 mean = _mm_div_ps(_mm_loadu_ps(sum + i + 4 * g), divisor);
      _mm_storeu_ps(height + i + 4 * g,
                    _mm_add_ps(_mm_and_ps(_mm_castsi128_ps(ok[g]), mean), zero));
    }
  }
  return i;
}

int pullColumnsSse2(const float* __restrict__ vs, const float* __restrict__ vh, int j, int j_end,
                    float* __restrict__ value, float* __restrict__ ok) {
  const __m128 quarter = _mm_set1_ps(0.25f), three = _mm_set1_ps(0.75f), half_w = _mm_set1_ps(0.5f);
  const __m128 one = _mm_set1_ps(1.0f);
  for (; j + 4 <= j_end; j += 4) {
    const __m128 s_a = _mm_loadu_ps(vs + j), s_b = _mm_loadu_ps(vs + j + 1),
                 s_c = _mm_loadu_ps(vs + j + 2);
    const __m128 h_a = _mm_loadu_ps(vh + j), h_b = _mm_loadu_ps(vh + j + 1),
                 h_c = _mm_loadu_ps(vh + j + 2);
    const __m128 we = _mm_add_ps(_mm_mul_ps(quarter, s_a), _mm_mul_ps(three, s_b));
    const __m128 wo = _mm_add_ps(_mm_mul_ps(three, s_b), _mm_mul_ps(quarter, s_c));
    const __m128 fe = _mm_div_ps(_mm_add_ps(_mm_mul_ps(quarter, h_a), _mm_mul_ps(three, h_b)),
                                 _mm_max_ps(we, half_w));
    const __m128 fo = _mm_div_ps(_mm_add_ps(_mm_mul_ps(three, h_b), _mm_mul_ps(quarter, h_c)),
                                 _mm_max_ps(wo, half_w));
    const __m128 ke = _mm_and_ps(_mm_cmpge_ps(we, half_w), one);
    const __m128 ko = _mm_and_ps(_mm_cmpge_ps(wo, half_w), one);
    // Interleaved into fine-column order: 2j, 2j + 1, ...
    _mm_storeu_ps(value + 2 * j, _mm_unpacklo_ps(fe, fo));
    _mm_storeu_ps(value + 2 * j + 4, _mm_unpackhi_ps(fe, fo));
    _mm_storeu_ps(ok + 2 * j, _mm_unpacklo_ps(ke, ko));
    _mm_storeu_ps(ok + 2 * j + 4, _mm_unpackhi_ps(ke, ko));
  }
  return j;
}

}  // namespace dlo::simd

#endif  // __SSE2__
