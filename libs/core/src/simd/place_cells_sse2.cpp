// The SSE2 kernel of placing cells against the reference's centroid offsets:
// place_cells_scalar.cpp's arithmetic in its order, four cells at a time. The offsets are read
// lane by lane; the Newton steps, with their divisions and square roots, run on all four at
// once, and a lane that has converged (or whose lattice folds) keeps its place from then on,
// as the scalar loop breaks.
#include "simd/place_cells_kernels.h"

#ifdef __SSE2__
#include <emmintrin.h>

#include "simd/pose_sse2.h"

namespace dlo::simd {

namespace {

/// Lanes of `a` where `mask` is set, else those of `b`.
inline __m128 select(__m128 mask, __m128 a, __m128 b) {
  return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}

/// std::clamp(x, lo, hi) lane by lane: lo where x < lo, else hi where hi < x, else x.
inline __m128 clamp(__m128 x, __m128 lo, __m128 hi) {
  return select(_mm_cmplt_ps(x, lo), lo, select(_mm_cmplt_ps(hi, x), hi, x));
}

/// The scalar floorInt(): truncated, one less where truncation went up.
inline __m128i floorInt(__m128 x) {
  const __m128i i = _mm_cvttps_epi32(x);
  return _mm_add_epi32(i, _mm_castps_si128(_mm_cmplt_ps(x, _mm_cvtepi32_ps(i))));
}

inline __m128 add(__m128 a, __m128 b) {
  return _mm_add_ps(a, b);
}
inline __m128 sub(__m128 a, __m128 b) {
  return _mm_sub_ps(a, b);
}
inline __m128 mul(__m128 a, __m128 b) {
  return _mm_mul_ps(a, b);
}

}  // namespace

size_t placeCellsSse2(const OffsetLattice& lattice, const SelectedCell* cells,
                      const Eigen::Vector2f* cell_offsets, size_t from, size_t n,
                      const Eigen::Matrix3f& R, const Eigen::Vector3f& t, bool warm_start,
                      Eigen::Vector2f* warm, SelectedCell* out) {
  const int cols = lattice.cols, rows = lattice.rows;
  const __m128 inv_res = _mm_set1_ps(lattice.inv_res);
  const __m128 x_c = _mm_set1_ps(lattice.x_c), y_c = _mm_set1_ps(lattice.y_c);
  const __m128 lo = _mm_set1_ps(-2.0f);
  const __m128 u_max = _mm_set1_ps(static_cast<float>(cols + 1));
  const __m128 v_max = _mm_set1_ps(static_cast<float>(rows + 1));
  const __m128 one = _mm_set1_ps(1.0f), zero = _mm_setzero_ps(), sign = _mm_set1_ps(-0.0f);
  const __m128 tiny = _mm_set1_ps(1e-10f), fold = _mm_set1_ps(0.1f);
  const __m128 limit = _mm_set1_ps(lattice.limit);
  const __m128 all = _mm_castsi128_ps(_mm_set1_epi32(-1));
  const PoseSse2 pose(R, t);
  const int steps = warm_start ? kWarmNewtonSteps : kColdNewtonSteps;
  size_t k = from;
  for (; k + 4 <= n; k += 4) {
    const SelectedCell* c = cells + k;
    const Eigen::Vector2f* co = cell_offsets + k;
    const __m128 x = add(_mm_setr_ps(c[0].x, c[1].x, c[2].x, c[3].x),
                         _mm_setr_ps(co[0].x(), co[1].x(), co[2].x(), co[3].x()));
    const __m128 y = add(_mm_setr_ps(c[0].y, c[1].y, c[2].y, c[3].y),
                         _mm_setr_ps(co[0].y(), co[1].y(), co[2].y(), co[3].y()));
    const __m128 h = _mm_setr_ps(c[0].h, c[1].h, c[2].h, c[3].h);
    const __m128 tx = pose.apply(0, x, y, h), ty = pose.apply(1, x, y, h);
    __m128 ax = tx, ay = ty;
    if (warm_start) {
      const Eigen::Vector2f* w = warm + k;
      ax = sub(tx, _mm_setr_ps(w[0].x(), w[1].x(), w[2].x(), w[3].x()));
      ay = sub(ty, _mm_setr_ps(w[0].y(), w[1].y(), w[2].y(), w[3].y()));
    }
    __m128 active = all;
    for (int it = 0; it < steps; ++it) {
      const int live = _mm_movemask_ps(active);
      if (live == 0) break;
      const __m128 u = clamp(mul(sub(ax, x_c), inv_res), lo, u_max);
      const __m128 v = clamp(mul(sub(ay, y_c), inv_res), lo, v_max);
      const __m128i c0 = floorInt(u), r0 = floorInt(v);
      const __m128 fu = sub(u, _mm_cvtepi32_ps(c0)), fv = sub(v, _mm_cvtepi32_ps(r0));
      alignas(16) int ci[4], ri[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(ci), c0);
      _mm_store_si128(reinterpret_cast<__m128i*>(ri), r0);
      // The four offsets around each live lane: x and y of d00, d10, d01, d11.
      alignas(16) float d[8][4] = {};
      for (int j = 0; j < 4; ++j) {
        if (((live >> j) & 1) == 0) continue;
        Eigen::Vector2f d00, d10, d01, d11;
        cornerOffsets(lattice, ri[j], ci[j], d00, d10, d01, d11);
        d[0][j] = d00.x();
        d[1][j] = d00.y();
        d[2][j] = d10.x();
        d[3][j] = d10.y();
        d[4][j] = d01.x();
        d[5][j] = d01.y();
        d[6][j] = d11.x();
        d[7][j] = d11.y();
      }
      const __m128 d00x = _mm_load_ps(d[0]), d00y = _mm_load_ps(d[1]);
      const __m128 d10x = _mm_load_ps(d[2]), d10y = _mm_load_ps(d[3]);
      const __m128 d01x = _mm_load_ps(d[4]), d01y = _mm_load_ps(d[5]);
      const __m128 d11x = _mm_load_ps(d[6]), d11y = _mm_load_ps(d[7]);
      const __m128 gu = sub(one, fu), gv = sub(one, fv);
      // d = (1 - fv) ((1 - fu) d00 + fu d10) + fv ((1 - fu) d01 + fu d11)
      const __m128 dx = add(mul(gv, add(mul(gu, d00x), mul(fu, d10x))),
                            mul(fv, add(mul(gu, d01x), mul(fu, d11x))));
      const __m128 dy = add(mul(gv, add(mul(gu, d00y), mul(fu, d10y))),
                            mul(fv, add(mul(gu, d01y), mul(fu, d11y))));
      const __m128 ex = sub(add(ax, dx), tx), ey = sub(add(ay, dy), ty);
      const __m128 converged = _mm_cmplt_ps(add(mul(ex, ex), mul(ey, ey)), tiny);
      // J = I + (columns), as J.col(i) += ...
      const __m128 j00 =
          add(one, mul(add(mul(gv, sub(d10x, d00x)), mul(fv, sub(d11x, d01x))), inv_res));
      const __m128 j10 =
          add(zero, mul(add(mul(gv, sub(d10y, d00y)), mul(fv, sub(d11y, d01y))), inv_res));
      const __m128 j01 =
          add(zero, mul(add(mul(gu, sub(d01x, d00x)), mul(fu, sub(d11x, d10x))), inv_res));
      const __m128 j11 =
          add(one, mul(add(mul(gu, sub(d01y, d00y)), mul(fu, sub(d11y, d10y))), inv_res));
      const __m128 det = sub(mul(j00, j11), mul(j10, j01));
      const __m128 folded = _mm_cmplt_ps(det, fold);
      // Eigen's 2x2 inverse: (j11, -j01; -j10, j00) times 1 / det.
      const __m128 invdet = _mm_div_ps(one, det);
      const __m128 i00 = mul(j11, invdet), i10 = mul(_mm_xor_ps(j10, sign), invdet);
      const __m128 i01 = mul(_mm_xor_ps(j01, sign), invdet), i11 = mul(j00, invdet);
      __m128 sx = add(mul(i00, ex), mul(i01, ey)), sy = add(mul(i10, ex), mul(i11, ey));
      const __m128 norm = _mm_sqrt_ps(add(mul(sx, sx), mul(sy, sy)));
      const __m128 over = _mm_cmpgt_ps(norm, limit);
      const __m128 scale = _mm_div_ps(limit, norm);
      sx = select(over, mul(sx, scale), sx);
      sy = select(over, mul(sy, scale), sy);
      const __m128 moving = _mm_andnot_ps(_mm_or_ps(converged, folded), active);
      ax = select(moving, sub(ax, sx), ax);
      ay = select(moving, sub(ay, sy), ay);
      active = moving;
    }
    const __m128 dx = sub(tx, ax), dy = sub(ty, ay);
    // Moved by -d in the reference: by -R^T d in the scan.
    const __m128 bx = pose.applyTransposed(0, dx, dy, zero);
    const __m128 by = pose.applyTransposed(1, dx, dy, zero);
    alignas(16) float ds[2][4], ps[2][4];
    _mm_store_ps(ds[0], dx);
    _mm_store_ps(ds[1], dy);
    _mm_store_ps(ps[0], sub(x, bx));
    _mm_store_ps(ps[1], sub(y, by));
    for (int j = 0; j < 4; ++j) {
      if (warm != nullptr) warm[k + j] = Eigen::Vector2f(ds[0][j], ds[1][j]);
      SelectedCell placed = c[j];
      placed.x = ps[0][j];
      placed.y = ps[1][j];
      out[k + j] = placed;
    }
  }
  return k;
}

}  // namespace dlo::simd

#endif  // __SSE2__
