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

namespace detail {

/// w00 p0[0] + w01 p0[1] + w10 p1[0] + w11 p1[1] for each of h, gx and gy, summed left to
/// right: the scalar reference of blendCellsSse2().
inline void blendCellsScalar(float w00, float w01, float w10, float w11, const GradientCell* p0,
                             const GradientCell* p1, HeightSample& out) {
  out.h = w00 * p0[0].h + w01 * p0[1].h + w10 * p1[0].h + w11 * p1[1].h;
  out.gx = w00 * p0[0].gx + w01 * p0[1].gx + w10 * p1[0].gx + w11 * p1[1].gx;
  out.gy = w00 * p0[0].gy + w01 * p0[1].gy + w10 * p1[0].gy + w11 * p1[1].gy;
}

#ifdef __SSE2__
/// blendCellsScalar() with h, gx and gy in three lanes of one vector (a cell is h gx gy ok):
/// the same operations in the same order, lane by lane, so the same results bit for bit
/// (tests/core/test_sample_cells_kernels.cpp). It stays here, inline, rather than in
/// libs/core/src/simd/ with the other kernels: HeightSampler::sample() is the innermost call of
/// every residual (height_residual.h), and a call into another file per sample would cost more
/// than the blend itself.
inline void blendCellsSse2(float w00, float w01, float w10, float w11, const GradientCell* p0,
                           const GradientCell* p1, HeightSample& out) {
  static_assert(sizeof(GradientCell) == 4 * sizeof(float), "h gx gy ok, packed");
  const __m128 s =
      _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_set1_ps(w00), _mm_loadu_ps(&p0[0].h)),
                                       _mm_mul_ps(_mm_set1_ps(w01), _mm_loadu_ps(&p0[1].h))),
                            _mm_mul_ps(_mm_set1_ps(w10), _mm_loadu_ps(&p1[0].h))),
                 _mm_mul_ps(_mm_set1_ps(w11), _mm_loadu_ps(&p1[1].h)));
  out.h = _mm_cvtss_f32(s);
  out.gx = _mm_cvtss_f32(_mm_shuffle_ps(s, s, _MM_SHUFFLE(1, 1, 1, 1)));
  out.gy = _mm_cvtss_f32(_mm_shuffle_ps(s, s, _MM_SHUFFLE(2, 2, 2, 2)));
}
#endif

}  // namespace detail

/// Reference-side lookup: owns the gradient field of one grid level and interpolates it.
class HeightSampler {
 public:
  HeightSampler() = default;
  HeightSampler(const GridGeometry& geometry, GradientField gradients)
      : geometry_(geometry),
        inv_resolution_(1.0 / geometry.resolution),
        field_(std::move(gradients)) {}

  /// Samples at metric (x, y) in the grid frame. Returns false when (x, y) is outside the grid
  /// or any of the four surrounding cells lacks a valid gradient. Several cells at a time:
  /// libs/core/src/simd/sample_cells_sse2.cpp, with the same arithmetic.
  bool sample(double x, double y, HeightSample& out) const {
    float a, b;
    const GradientCell* p0 = lowerLeft(x, y, a, b);
    if (p0 == nullptr) return false;
    const GradientCell* p1 = p0 + geometry_.cols;
    // ok is 1 or 0: one test of the product instead of four branches on data.
    if (p0[0].ok * p0[1].ok * p1[0].ok * p1[1].ok == 0.0f) return false;
    const float w00 = (1 - a) * (1 - b), w01 = a * (1 - b), w10 = (1 - a) * b, w11 = a * b;
#ifdef __SSE2__
    detail::blendCellsSse2(w00, w01, w10, w11, p0, p1, out);
#else
    detail::blendCellsScalar(w00, w01, w10, w11, p0, p1, out);
#endif
    return true;
  }

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
  /// 1 / geometry().resolution, as lowerLeft() uses it.
  double inverseResolution() const {
    return inv_resolution_;
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
