#include "dlo/core/deskew.h"

#include <algorithm>
#include <cmath>

#include "simd/deskew_kernels.h"

namespace dlo {

RowMajorPose::RowMajorPose(const Eigen::Isometry3f& pose) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = pose.linear()(r, c);
    m[4 * r + 3] = pose.translation()(r);
  }
}

SweepMotion::SweepMotion(const std::vector<float>& times, const Vector6d& velocity, int bins) {
  if (times.empty() || bins < 1) return;
  // The range of the times (a sweep has 10^5 of them), vectorised; a NaN time is skipped.
  const float* t = times.data();
  const size_t n = times.size();
  float lo = t[0], hi = t[0];
  size_t k = 0;
#ifdef __SSE2__
  k = simd::widenTimeRangeSse2(t, k, n, lo, hi);
#endif
  simd::widenTimeRangeScalar(t, k, n, lo, hi);
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
  // The same bins as bin() (simd::timeBinsScalar() is its arithmetic), several at a time.
  const simd::TimeBins quantiser{lo_, span_, bins_};
  size_t k = 0;
#ifdef __SSE2__
  k = simd::timeBinsSse2(quantiser, t, k, n, out);
#endif
  simd::timeBinsScalar(quantiser, t, k, n, out);
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
