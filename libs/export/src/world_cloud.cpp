#include "dlo/export/world_cloud.h"

namespace dlo {

void forEachWorldCloud(const SlamMap& map,
                       const std::function<void(const WeightedCloud& world_points)>& visit) {
  WeightedCloud buffer, world;
  for (size_t i = 0; i < map.keyframes.size(); ++i) {
    const WeightedCloud& cloud = map.keyframeCloud(i, buffer);
    const Eigen::Isometry3f T = map.keyframes[i].pose.cast<float>();
    world.resize(cloud.size());
    for (size_t j = 0; j < cloud.size(); ++j) world[j] = WeightedPoint{T * cloud[j].p, cloud[j].n};
    visit(world);
  }
}

WeightedCloud worldCloud(const SlamMap& map, double voxel) {
  if (voxel > 0.0) {
    VoxelMerger merged(voxel);
    forEachWorldCloud(map, [&](const WeightedCloud& c) { merged.add(c); });
    return merged.result();
  }
  WeightedCloud all;
  forEachWorldCloud(map,
                    [&](const WeightedCloud& c) { all.insert(all.end(), c.begin(), c.end()); });
  return all;
}

}  // namespace dlo
