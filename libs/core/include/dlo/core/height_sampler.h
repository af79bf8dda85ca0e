/// \file height_sampler.h
/// \brief Bilinear interpolation of heights and gradients of a reference grid.
#pragma once

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "dlo/core/gradient_field.h"
#include "dlo/core/grid_geometry.h"

namespace dlo {

/// Height and gradient at a continuous position, from bilinear interpolation.
struct HeightSample {
  float h = 0.0f;   ///< metres
  float gx = 0.0f;  ///< dH/dx, m/m
  float gy = 0.0f;  ///< dH/dy, m/m
};

/// Reference-side lookup: owns the gradient field of one grid level and interpolates it.
class HeightSampler {
 public:
  HeightSampler() = default;
  HeightSampler(const GridGeometry& geometry, GradientField gradients)
      : geometry_(geometry),
        inv_resolution_(1.0 / geometry.resolution),
        field_(std::move(gradients)) {}

  /// Samples at metric (x, y) in the grid frame. Returns false when (x, y) is outside the grid
  /// or any of the four surrounding cells lacks a valid gradient.
  bool sample(double x, double y, HeightSample& out) const {
    float a, b;
    const GradientCell* p0 = lowerLeft(x, y, a, b);
    if (p0 == nullptr) return false;
    const GradientCell* p1 = p0 + geometry_.cols;
    // ok is 1 or 0: one test of the product instead of four branches on data.
    if (p0[0].ok * p0[1].ok * p1[0].ok * p1[1].ok == 0.0f) return false;
    const float w00 = (1 - a) * (1 - b), w01 = a * (1 - b), w10 = (1 - a) * b, w11 = a * b;
#ifdef __SSE2__
    // The cells are (h, gx, gy, ok): all three interpolated at once, with the scalar code's
    // operations in its order, lane by lane.
    static_assert(sizeof(GradientCell) == 4 * sizeof(float), "h gx gy ok, packed");
    const __m128 s =
        _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(w00), _mm_loadu_ps(&p0[0].h)),
                                         _mm_mul_ps(_mm_set1_ps(w01), _mm_loadu_ps(&p0[1].h))),
                              _mm_mul_ps(_mm_set1_ps(w10), _mm_loadu_ps(&p1[0].h))),
                   _mm_mul_ps(_mm_set1_ps(w11), _mm_loadu_ps(&p1[1].h)));
    out.h = _mm_cvtss_f32(s);
    out.gx = _mm_cvtss_f32(_mm_shuffle_ps(s, s, _MM_SHUFFLE(1, 1, 1, 1)));
    out.gy = _mm_cvtss_f32(_mm_shuffle_ps(s, s, _MM_SHUFFLE(2, 2, 2, 2)));
#else
    out.h = w00 * p0[0].h + w01 * p0[1].h + w10 * p1[0].h + w11 * p1[1].h;
    out.gx = w00 * p0[0].gx + w01 * p0[1].gx + w10 * p1[0].gx + w11 * p1[1].gx;
    out.gy = w00 * p0[0].gy + w01 * p0[1].gy + w10 * p1[0].gy + w11 * p1[1].gy;
#endif
    return true;
  }

#ifdef __SSE2__
  /// sample() at four points (x, y lanes), each lane with sample()'s arithmetic in its order,
  /// so the results are the same bit for bit: out[i] = (h, gx, gy, 1) where sample() would
  /// return true, and ok = 0 (the rest unspecified) where it would return false. The bounds
  /// arithmetic runs two lanes at a time and the interpolation without a branch, which lets a
  /// loop over many points overlap their reads; used by the Gauss-Newton linearisation.
  void sample4(__m128 x, __m128 y, GradientCell out[4]) const {
    const int cols = geometry_.cols;
    // The loads below read the four cells from the lower-left one; lanes outside the grid read
    // cell 0's square instead, which exists only in a grid of at least 2 x 2 cells (a smaller
    // one has no lane inside).
    if (cols < 2 || geometry_.rows < 2) {
      for (int i = 0; i < 4; ++i) out[i].ok = 0.0f;
      return;
    }
    const __m128d x0 = _mm_set1_pd(geometry_.x_min), y0 = _mm_set1_pd(geometry_.y_min);
    const __m128d inv = _mm_set1_pd(inv_resolution_), half = _mm_set1_pd(0.5);
    const __m128d u_end = _mm_set1_pd(cols - 1), v_end = _mm_set1_pd(geometry_.rows - 1);
    const __m128d zero = _mm_setzero_pd();
    // The fractions of lanes 2 pair and 2 pair + 1 in the low half of each; joined in registers
    // (stored as floats and reloaded as a vector, they stalled store-to-load forwarding).
    __m128 fa[2], fb[2];
    int at[4];
    for (int pair = 0; pair < 2; ++pair) {
      // lowerLeft() for lanes 2 pair and 2 pair + 1.
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
      const GradientCell* p0 = field_.cells.data() + (at[i] < 0 ? 0 : at[i]);
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
#endif

  /// Asks for the cache lines sample(x, y) reads, for a sample() later; a hint only.
  void prefetch(double x, double y) const {
    float a, b;
    const GradientCell* p0 = lowerLeft(x, y, a, b);
    if (p0 == nullptr) return;
    __builtin_prefetch(p0);
    __builtin_prefetch(p0 + geometry_.cols);
  }

  /// Recomputes the gradients of `grid` in place, reusing this sampler's memory.
  void rebuild(const HeightGrid& grid) {
    geometry_ = grid.geometry();
    inv_resolution_ = 1.0 / geometry_.resolution;
    computeGradients(grid, field_);
  }

  const GridGeometry& geometry() const {
    return geometry_;
  }
  const GradientField& gradients() const {
    return field_;
  }

 private:
  /// The lower-left of the four cells around (x, y) and the bilinear fractions (a along x, b
  /// along y), or nullptr when (x, y) is outside the grid's cell centres.
  const GradientCell* lowerLeft(double x, double y, float& a, float& b) const {
    const double u = (x - geometry_.x_min) * inv_resolution_ - 0.5;
    const double v = (y - geometry_.y_min) * inv_resolution_ - 0.5;
    if (!(u >= 0.0 && v >= 0.0 && u < geometry_.cols - 1 && v < geometry_.rows - 1)) return nullptr;
    const int c = static_cast<int>(u);
    const int r = static_cast<int>(v);
    a = static_cast<float>(u - c);
    b = static_cast<float>(v - r);
    return &field_.cells[r * geometry_.cols + c];
  }

  GridGeometry geometry_;
  double inv_resolution_ = 1.0;
  GradientField field_;
};

}  // namespace dlo
