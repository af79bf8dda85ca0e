#include "dlo/core/deskew.h"

#include <algorithm>
#include <cmath>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace dlo {

RowMajorPose::RowMajorPose(const Eigen::Isometry3f& pose) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = pose.linear()(r, c);
    m[4 * r + 3] = pose.translation()(r);
  }
}

SweepMotion::SweepMotion(const std::vector<float>& times, const Vector6d& velocity, int bins) {
  if (times.empty() || bins < 1) return;
  // The range of the times, four lanes at a time (a sweep has 10^5 of them). A NaN time is
  // skipped: MINPS and MAXPS return their second operand when either is NaN.
  const float* t = times.data();
  const size_t n = times.size();
  float lo = t[0], hi = t[0];
  size_t k = 0;
#ifdef __SSE2__
  if (n >= 4) {
    __m128 vlo = _mm_set1_ps(lo), vhi = _mm_set1_ps(hi);
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
  }
#endif
  for (; k < n; ++k) {
    lo = std::min(lo, t[k]);  // (t < lo) ? t : lo, false for NaN
    hi = std::max(hi, t[k]);
  }
  const float span = std::max(hi - lo, 1e-9f);
  times_ = &times;
  lo_ = lo;
  span_ = span;
  bins_ = bins;
  motion_.resize(static_cast<size_t>(bins) + 1);
  for (int b = 0; b <= bins; ++b) {
    const double t = lo + static_cast<double>(span) * b / bins;
    motion_[b] = RowMajorPose(expSE3(velocity * t).cast<float>());
  }
}

void SweepMotion::bins(const float* t, size_t n, int* out) const {
  size_t k = 0;
#ifdef __SSE2__
  // bin()'s operations, four times at a time; f lies in [0, bins] for the times the motion was
  // tabulated over (a NaN time becomes 0, as the clamp in bin() makes it).
  const __m128 lo = _mm_set1_ps(lo_), span = _mm_set1_ps(span_);
  const __m128 top = _mm_set1_ps(static_cast<float>(bins_));
  const __m128 zero = _mm_setzero_ps(), half = _mm_set1_ps(0.5f);
  for (; k + 4 <= n; k += 4) {
    __m128 f = _mm_mul_ps(_mm_div_ps(_mm_sub_ps(_mm_loadu_ps(t + k), lo), span), top);
    f = _mm_min_ps(_mm_max_ps(f, zero), top);  // max(NaN, 0) is 0
    const __m128i i = _mm_cvttps_epi32(f);
    // Rounded half up: all ones (-1) where the fraction is at least 1/2.
    const __m128i up = _mm_castps_si128(_mm_cmpge_ps(_mm_sub_ps(f, _mm_cvtepi32_ps(i)), half));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + k), _mm_sub_epi32(i, up));
  }
#endif
  for (; k < n; ++k) out[k] = bin(t[k]);
}

void SweepMotion::apply(size_t first, const Eigen::Vector3f* p, size_t n,
                        Eigen::Vector3f* out) const {
  constexpr size_t kBatch = 256;
  int bin[kBatch];
  for (size_t from = 0; from < n; from += kBatch) {
    const size_t m = std::min(kBatch, n - from);
    bins(times_->data() + first + from, m, bin);
    for (size_t k = 0; k < m; ++k) out[from + k] = pose(bin[k]) * p[from + k];
  }
}

PointCloud deskew(const PointCloud& points, const std::vector<float>& times,
                  const Vector6d& velocity, int bins) {
  if (times.size() != points.size() || points.empty()) return points;
  return deskew(points, SweepMotion(times, velocity, bins));
}

PointCloud deskew(const PointCloud& points, const SweepMotion& motion) {
  PointCloud out;
  deskew(points, motion, out);
  return out;
}

void deskew(const PointCloud& points, const SweepMotion& motion, PointCloud& out) {
  if (!motion.fits(points.size())) {
    out = points;
    return;
  }
  out.resize(points.size());
  motion.apply(0, points.data(), points.size(), out.data());
}

}  // namespace dlo
