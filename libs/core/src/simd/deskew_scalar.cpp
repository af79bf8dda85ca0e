// The scalar references of SweepMotion's kernels (simd/deskew_kernels.h).
#include <algorithm>

#include "simd/deskew_kernels.h"

namespace dlo::simd {

size_t widenTimeRangeScalar(const float* t, size_t from, size_t n, float& lo, float& hi) {
  for (size_t k = from; k < n; ++k) {
    lo = std::min(lo, t[k]);  // (t < lo) ? t : lo, false for NaN
    hi = std::max(hi, t[k]);
  }
  return n;
}

size_t timeBinsScalar(const TimeBins& b, const float* t, size_t from, size_t n, int* out) {
  for (size_t k = from; k < n; ++k) {
    // The nearest bin, as std::lround would round (half away from zero) but without a library
    // call per point: f - trunc(f) is exact for these magnitudes.
    const float f = (t[k] - b.lo) / b.span * static_cast<float>(b.bins);
    const int i = static_cast<int>(f);
    out[k] = std::clamp(i + (f - static_cast<float>(i) >= 0.5f ? 1 : 0), 0, b.bins);
  }
  return n;
}

}  // namespace dlo::simd
