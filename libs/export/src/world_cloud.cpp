#include "dlo/export/world_cloud.h"

namespace dlo {

WeightedCloud worldCloud(const SlamMap& map, double voxel) {
  WeightedCloud merged;
  size_t total = 0;
  for (const Keyframe& kf : map.keyframes) total += kf.cloud.size();
  merged.reserve(total);
  for (const Keyframe& kf : map.keyframes) {
    const Eigen::Isometry3f T = kf.pose.cast<float>();
    for (const WeightedPoint& w : kf.cloud) merged.push_back(WeightedPoint{T * w.p, w.n});
  }
  return voxel > 0.0 ? voxelise(merged, voxel) : merged;
}

}  // namespace dlo
