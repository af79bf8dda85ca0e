#include "dlo/mrpt/point_conversion.h"

#include <cmath>

namespace dlo {

namespace {

void appendTransformed(const mrpt::poses::CPose3D& pose, const float* xs, const float* ys,
                       const float* zs, size_t n, PointCloud& out) {
  const Eigen::Matrix3f R = pose.getRotationMatrix().asEigen().cast<float>();
  const Eigen::Vector3f t(static_cast<float>(pose.x()), static_cast<float>(pose.y()),
                          static_cast<float>(pose.z()));
  out.reserve(out.size() + n);
  for (size_t i = 0; i < n; ++i) {
    if (!(std::isfinite(xs[i]) && std::isfinite(ys[i]) && std::isfinite(zs[i]))) continue;
    out.push_back(R * Eigen::Vector3f(xs[i], ys[i], zs[i]) + t);
  }
}

}  // namespace

PointCloud toPointCloud(const mrpt::maps::CPointsMap& map) {
  PointCloud out;
  const auto& xs = map.getPointsBufferRef_x();
  const auto& ys = map.getPointsBufferRef_y();
  const auto& zs = map.getPointsBufferRef_z();
  appendTransformed(mrpt::poses::CPose3D(), xs.data(), ys.data(), zs.data(), xs.size(), out);
  return out;
}

}  // namespace dlo
