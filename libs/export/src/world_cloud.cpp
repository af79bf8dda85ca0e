#include "dlo/export/world_cloud.h"

namespace dlo {

WeightedCloud worldCloud(const SlamMap& map, double voxel) {
  WeightedCloud merged;
  size_t total = 0;
  for (const Keyframe& kf : map.keyframes) total += kf.cloud.size();
  merged.reserve(total);
  for (const Keyframe& kf : map.keyframes) {
    const WeightedCloud world = transformed(kf.cloud, kf.pose);
    merged.insert(merged.end(), world.begin(), world.end());
  }
  return voxel > 0.0 ? voxelise(merged, voxel) : merged;
}

}  // namespace dlo
