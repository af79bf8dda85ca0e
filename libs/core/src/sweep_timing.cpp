#include "dlo/core/sweep_timing.h"

#include <algorithm>
#include <cmath>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace dlo {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kTwoPiF = 6.28318530717958647692f;
constexpr float kPiF = 3.14159265358979323846f;

/// atan2(y, x) in [-pi, pi] within 2e-5 rad (1e-3 deg, a microsecond of a 10 Hz sweep), with no
/// branch and no library call: a sweep has 100k points and std::atan2 cost more than the grid.
/// Minimax polynomial for atan on [0, 1], then the octant.
inline float fastAtan2(float y, float x) {
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

#ifdef __SSE2__
/// fastAtan2 of four lanes, the same operations in the same order.
inline __m128 fastAtan2(__m128 y, __m128 x) {
  const __m128 sign = _mm_set1_ps(-0.0f), zero = _mm_setzero_ps();
  const __m128 ax = _mm_andnot_ps(sign, x), ay = _mm_andnot_ps(sign, y);
  const __m128 hi = _mm_max_ps(ax, ay), lo = _mm_min_ps(ax, ay);
  const __m128 a = _mm_div_ps(lo, _mm_max_ps(hi, _mm_set1_ps(1e-30f)));
  const __m128 s = _mm_mul_ps(a, a);
  __m128 r = _mm_add_ps(_mm_mul_ps(_mm_set1_ps(-0.0117212f), s), _mm_set1_ps(0.05265332f));
  r = _mm_sub_ps(_mm_mul_ps(r, s), _mm_set1_ps(0.11643287f));
  r = _mm_add_ps(_mm_mul_ps(r, s), _mm_set1_ps(0.19354346f));
  r = _mm_sub_ps(_mm_mul_ps(r, s), _mm_set1_ps(0.33262347f));
  r = _mm_add_ps(_mm_mul_ps(r, s), _mm_set1_ps(0.99997726f));
  r = _mm_mul_ps(r, a);
  const auto select = [](__m128 mask, __m128 yes, __m128 no) {
    return _mm_or_ps(_mm_and_ps(mask, yes), _mm_andnot_ps(mask, no));
  };
  r = select(_mm_cmpgt_ps(ay, ax), _mm_sub_ps(_mm_set1_ps(1.57079632679f), r), r);
  r = select(_mm_cmplt_ps(x, zero), _mm_sub_ps(_mm_set1_ps(3.14159265359f), r), r);
  return select(_mm_cmplt_ps(y, zero), _mm_sub_ps(zero, r), r);
}
#endif

/// Angle in [-pi, pi].
double wrapPi(double a) {
  return std::remainder(a, 2.0 * kPi);
}

/// Points whose azimuth means something: finite and not on the spin axis.
bool usable(const Eigen::Vector3f& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()) &&
         p.head<2>().squaredNorm() > 0.25f;
}

/// Circular mean azimuth of points[idx[first, last)], or NaN when they spread over too wide an
/// arc for a mean to mean anything (resultant below half their number).
double meanAzimuth(const PointCloud& points, const std::vector<size_t>& idx, size_t first,
                   size_t last) {
  double sx = 0.0, sy = 0.0;
  for (size_t k = first; k < last; ++k) {
    const Eigen::Vector3f& p = points[idx[k]];
    const float inv = 1.0f / std::sqrt(p.x() * p.x() + p.y() * p.y());
    sx += static_cast<double>(p.x() * inv);
    sy += static_cast<double>(p.y() * inv);
  }
  if (std::hypot(sx, sy) < 0.5 * static_cast<double>(last - first)) return std::nan("");
  return std::atan2(sy, sx);
}

/// Reads the spin direction and start azimuth off the storage order; false if the order does
/// not follow the sweep.
bool fromOrder(const PointCloud& points, SweepTimingEstimate& out) {
  // A sample of the cloud in storage order is enough to see the order: some 16,000 points, so
  // that this costs little next to the times themselves.
  constexpr size_t kSample = 16384;
  const size_t stride = std::max<size_t>(1, points.size() / kSample);
  thread_local std::vector<size_t> idx;
  idx.clear();
  for (size_t i = 0; i < points.size(); i += stride) {
    if (usable(points[i])) idx.push_back(i);
  }
  constexpr size_t kMinPoints = 256;
  if (idx.size() < kMinPoints) return false;
  // The azimuth along the storage order, averaged over chunks of consecutive points (a firing's
  // lasers have azimuth offsets of their own): in firing order it advances by a degree or two
  // per chunk, always in the spin direction; ring by ring it goes round once per ring, and in
  // a shuffled cloud the chunks have no mean direction at all.
  const size_t chunks = std::min<size_t>(256, idx.size() / 64);
  const size_t per = idx.size() / chunks;
  int forward = 0, backward = 0, steps = 0;
  double travelled = 0.0;
  double previous = std::nan("");
  for (size_t c = 0; c < chunks; ++c) {
    const double m = meanAzimuth(points, idx, c * per, (c + 1) * per);
    if (!std::isnan(m) && !std::isnan(previous)) {
      ++steps;
      const double d = wrapPi(m - previous);
      if (std::fabs(d) < kPi / 6.0 && std::fabs(d) > 1e-6) (d > 0.0 ? forward : backward)++;
      travelled += d;
    }
    previous = m;
  }
  // Nearly every step small and in one direction.
  const int agree = std::max(forward, backward);
  if (steps < 16 || agree < 0.8 * steps) return false;
  // And one revolution over the whole cloud: firing order, which is the order of time. A cloud
  // stored ring by ring goes round once per ring, and that order is the driver's, not the
  // sensor's: KITTI's files run counter-clockwise from the front in every ring, while the
  // sensor spins clockwise from behind.
  if (std::fabs(travelled) > 1.5 * 2.0 * kPi) return false;
  out.direction = forward > backward ? 1 : -1;
  // The seam lies between the last points and the first ones: halfway across the gap between
  // them, going in the spin direction (a partial sweep, whose gap is wide: just before the
  // first points).
  const size_t k = std::min<size_t>(32, idx.size() / 4);
  const double first = meanAzimuth(points, idx, 0, k);
  const double last = meanAzimuth(points, idx, idx.size() - k, idx.size());
  if (std::isnan(first)) return false;
  double gap = std::isnan(last) ? 0.0 : wrapPi(out.direction * (first - last));
  if (!(gap > 0.0 && gap < kPi / 6.0)) gap = 2.0 * kPi / 360.0;  // 1 degree before the first
  out.start_azimuth_deg = wrapPi(first - out.direction * 0.5 * gap) * 180.0 / kPi;
  out.from_order = true;
  return true;
}

}  // namespace

SweepTimingEstimate estimateSweepTimes(const PointCloud& points, const SweepTimingParams& params,
                                       std::vector<float>& times) {
  SweepTimingEstimate e;
  if (!fromOrder(points, e)) {
    e.from_order = false;
    e.direction = params.direction >= 0 ? 1 : -1;
    e.start_azimuth_deg = params.start_azimuth_deg;
  }
  times.resize(points.size());
  const float start = static_cast<float>(e.start_azimuth_deg * kPi / 180.0);
  const float dir = static_cast<float>(e.direction);
  // Seconds per radian of the sweep, and the time of its start relative to the stamp.
  const float scale = static_cast<float>(params.period / (2.0 * kPi));
  const float offset = static_cast<float>(-params.stamp_phase * params.period);
  // In firing order a point's place in the cloud is its time, roughly: the sweep's first
  // points lie near phase 0 and its last near a whole revolution. Near the seam the azimuth
  // alone cannot tell the two apart (a sweep overlaps itself by a firing or two, and each laser
  // has an azimuth offset of its own), and a point of the wrong end was timed a whole period
  // off: deskewed by a sweep's motion, a wedge of the scan straight ahead stood a metre from
  // where it was at 10 m/s. The azimuth's revolution is the one nearest the point's place.
  const bool ordered = e.from_order && !points.empty();
  const float per_point =
      ordered ? kTwoPiF / static_cast<float>(points.size()) : 0.0f;  // radians of sweep per point
  size_t i = 0;
#ifdef __SSE2__
  // Four points at a time, the scalar loop's operations lane by lane.
  const __m128 vdir = _mm_set1_ps(dir), vstart = _mm_set1_ps(start);
  const __m128 vscale = _mm_set1_ps(scale), voffset = _mm_set1_ps(offset);
  const __m128 two_pi = _mm_set1_ps(kTwoPiF), zero = _mm_setzero_ps();
  const __m128 vper_point = _mm_set1_ps(per_point), vpi = _mm_set1_ps(kPiF);
  const __m128 vminus_pi = _mm_set1_ps(-kPiF);
  for (; i + 4 <= points.size(); i += 4) {
    const Eigen::Vector3f* p = points.data() + i;
    const __m128 x = _mm_setr_ps(p[0].x(), p[1].x(), p[2].x(), p[3].x());
    const __m128 y = _mm_setr_ps(p[0].y(), p[1].y(), p[2].y(), p[3].y());
    __m128 a = _mm_mul_ps(vdir, _mm_sub_ps(fastAtan2(y, x), vstart));
    a = _mm_add_ps(a, _mm_and_ps(_mm_cmplt_ps(a, zero), two_pi));
    a = _mm_sub_ps(a, _mm_and_ps(_mm_cmpge_ps(a, two_pi), two_pi));
    if (ordered) {
      const float k = static_cast<float>(i);
      const __m128 expected = _mm_mul_ps(_mm_setr_ps(k, k + 1.0f, k + 2.0f, k + 3.0f), vper_point);
      const __m128 ahead = _mm_sub_ps(a, expected);
      a = _mm_sub_ps(a, _mm_and_ps(_mm_cmpgt_ps(ahead, vpi), two_pi));
      a = _mm_add_ps(a, _mm_and_ps(_mm_cmplt_ps(ahead, vminus_pi), two_pi));
    }
    const __m128 t = _mm_add_ps(_mm_mul_ps(a, vscale), voffset);
    // t - t is 0 unless t is infinite or NaN (a non-finite point): those get the stamp's time.
    _mm_storeu_ps(times.data() + i, _mm_and_ps(t, _mm_cmpeq_ps(_mm_sub_ps(t, t), zero)));
  }
#endif
  for (; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    // Angle travelled from the start in the spin direction, in [0, 2 pi): both angles lie in
    // [-pi, pi], so one turn added or taken brings it into range.
    float a = dir * (fastAtan2(p.y(), p.x()) - start);
    a += a < 0.0f ? kTwoPiF : 0.0f;
    a -= a >= kTwoPiF ? kTwoPiF : 0.0f;
    if (ordered) {
      const float ahead = a - static_cast<float>(i) * per_point;
      a -= ahead > kPiF ? kTwoPiF : 0.0f;
      a += ahead < -kPiF ? kTwoPiF : 0.0f;
    }
    const float t = a * scale + offset;
    times[i] = t - t == 0.0f ? t : 0.0f;
  }
  return e;
}

}  // namespace dlo
