#include "dlo/mrpt/point_conversion.h"

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
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

bool observationToPointCloud(const mrpt::obs::CObservation& obs, PointCloud& out) {
  out.clear();
  if (const auto* velo = dynamic_cast<const mrpt::obs::CObservationVelodyneScan*>(&obs)) {
    const mrpt::obs::CObservationVelodyneScan* src = velo;
    mrpt::obs::CObservationVelodyneScan copy;
    if (velo->point_cloud.size() == 0) {
      copy = *velo;
      copy.generatePointCloud();
      src = &copy;
    }
    const auto& pc = src->point_cloud;
    appendTransformed(src->sensorPose, pc.x.data(), pc.y.data(), pc.z.data(), pc.x.size(), out);
    return true;
  }
  if (const auto* pco = dynamic_cast<const mrpt::obs::CObservationPointCloud*>(&obs)) {
    if (!pco->pointcloud) return true;
    const auto& m = *pco->pointcloud;
    appendTransformed(pco->sensorPose, m.getPointsBufferRef_x().data(),
                      m.getPointsBufferRef_y().data(), m.getPointsBufferRef_z().data(), m.size(),
                      out);
    return true;
  }
  if (const auto* r3d = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(&obs)) {
    if (!r3d->hasPoints3D) return false;
    appendTransformed(r3d->sensorPose, r3d->points3D_x.data(), r3d->points3D_y.data(),
                      r3d->points3D_z.data(), r3d->points3D_x.size(), out);
    return true;
  }
  return false;
}

}  // namespace dlo
