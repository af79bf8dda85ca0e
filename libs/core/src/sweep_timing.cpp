#include "dlo/core/sweep_timing.h"

#include <algorithm>
#include <cmath>

#include "simd/sweep_timing_kernels.h"

namespace dlo {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kTwoPiF = 6.28318530717958647692f;

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
  const simd::SweepClock clock{start, dir, scale, offset, per_point, ordered};
  size_t i = 0;
#ifdef DLO_SIMD_AVX2_DISPATCH
  if (simd::hasAvx2())
    i = simd::sweepTimesAvx2(clock, points.data(), i, points.size(), times.data());
#endif
#ifdef __SSE2__
  i = simd::sweepTimesSse2(clock, points.data(), i, points.size(), times.data());
#endif
  simd::sweepTimesScalar(clock, points.data(), i, points.size(), times.data());
  return e;
}

void SweepPeriodEstimate::add(double time) {
  const double dt = time - last_;
  const bool interval = has_last_ && dt > 0.0 && dt <= 1.0;
  last_ = time;
  has_last_ = true;
  if (!interval) return;
  recent_.push_back(dt);
  if (recent_.size() > kWindow) recent_.pop_front();
  std::vector<double> v(recent_.begin(), recent_.end());
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (std::abs(dt - *mid) <= 0.2 * *mid) {
    sum_ += dt;
    ++counted_;
  }
}

double SweepPeriodEstimate::period(double fallback) const {
  return counted_ > 0 ? sum_ / static_cast<double>(counted_) : fallback;
}

}  // namespace dlo
