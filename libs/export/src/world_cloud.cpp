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

}  // namespace dlo
