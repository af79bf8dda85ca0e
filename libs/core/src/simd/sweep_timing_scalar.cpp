// The scalar reference of estimateSweepTimes()'s per-point loop (simd/sweep_timing_kernels.h).
#include <algorithm>
#include <cmath>

#include "simd/sweep_timing_kernels.h"

namespace dlo::simd {

namespace {
constexpr float kTwoPiF = 6.28318530717958647692f;
constexpr float kPiF = 3.14159265358979323846f;
}  // namespace

// A sweep has 100k points and std::atan2 cost more than the grid. Minimax polynomial for atan
// on [0, 1], then the octant; within 1e-3 deg, a microsecond of a 10 Hz sweep.
float fastAtan2(float y, float x) {
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float hi = std::max(ax, ay), lo = std::min(ax, ay);
  const float a = lo / std::max(hi, 1e-30f);  // 0 at the origin, NaN for NaN input
  const float s = a * a;
  float r =
      ((((-0.0117212f * s + 0.05265332f) * s - 0.11643287f) * s + 0.19354346f) * s - 0.33262347f) *
          s +
      0.99997726f;
  r *= a;
  r = ay > ax ? 1.57079632679f - r : r;
  r = x < 0.0f ? 3.14159265359f - r : r;
  return y < 0.0f ? -r : r;
}

size_t sweepTimesScalar(const SweepClock& c, const Eigen::Vector3f* p, size_t from, size_t n,
                        float* times) {
  for (size_t i = from; i < n; ++i) {
    // Angle travelled from the start in the spin direction, in [0, 2 pi): both angles lie in
    // [-pi, pi], so one turn added or taken brings it into range.
    float a = c.dir * (fastAtan2(p[i].y(), p[i].x()) - c.start);
    a += a < 0.0f ? kTwoPiF : 0.0f;
    a -= a >= kTwoPiF ? kTwoPiF : 0.0f;
    if (c.ordered) {
      const float ahead = a - static_cast<float>(i) * c.per_point;
      a -= ahead > kPiF ? kTwoPiF : 0.0f;
      a += ahead < -kPiF ? kTwoPiF : 0.0f;
    }
    const float t = a * c.scale + c.offset;
    times[i] = t - t == 0.0f ? t : 0.0f;
  }
  return n;
}

}  // namespace dlo::simd
