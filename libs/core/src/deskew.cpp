#include "dlo/core/deskew.h"

#include <algorithm>
#include <cmath>

namespace dlo {

PointCloud deskew(const PointCloud& points, const std::vector<float>& times,
                  const Vector6d& velocity, int bins) {
  if (times.size() != points.size() || points.empty() || bins < 1) return points;
  const auto [lo_it, hi_it] = std::minmax_element(times.begin(), times.end());
  const float lo = *lo_it, hi = *hi_it;
  const float span = std::max(hi - lo, 1e-9f);
  std::vector<Eigen::Isometry3f> motion(static_cast<size_t>(bins) + 1);
  for (int b = 0; b <= bins; ++b) {
    const double t = lo + static_cast<double>(span) * b / bins;
    motion[b] = expSE3(velocity * t).cast<float>();
  }
  PointCloud out(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const float f = (times[i] - lo) / span * static_cast<float>(bins);
    const int b = std::clamp(static_cast<int>(std::lround(f)), 0, bins);
    out[i] = motion[b] * points[i];
  }
  return out;
}

}  // namespace dlo
