#include "dlo/core/deskew.h"

#include <algorithm>
#include <cmath>

namespace dlo {

RowMajorPose::RowMajorPose(const Eigen::Isometry3f& pose) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = pose.linear()(r, c);
    m[4 * r + 3] = pose.translation()(r);
  }
}

SweepMotion::SweepMotion(const std::vector<float>& times, const Vector6d& velocity, int bins) {
  if (times.empty() || bins < 1) return;
  const auto [lo_it, hi_it] = std::minmax_element(times.begin(), times.end());
  const float lo = *lo_it, hi = *hi_it;
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
  for (size_t i = 0; i < points.size(); ++i) out[i] = motion.apply(i, points[i]);
}

}  // namespace dlo
