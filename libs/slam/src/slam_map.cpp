#include "dlo/slam/slam_map.h"

namespace dlo {

const WeightedCloud& SlamMap::keyframeCloud(size_t i, WeightedCloud& buffer) const {
  const Keyframe& k = keyframes.at(i);
  if (!k.spilled) return k.cloud;
  buffer = spill->read(k.slot);
  return buffer;
}

void SlamMap::spillKeyframeCloud(size_t i) {
  Keyframe& k = keyframes.at(i);
  if (k.spilled) return;
  if (!spill) spill = std::make_shared<CloudSpill>();
  k.slot = spill->write(k.cloud);
  k.spilled = true;
  WeightedCloud().swap(k.cloud);
}

size_t SlamMap::residentCloudBytes() const {
  size_t bytes = 0;
  for (const Keyframe& k : keyframes) bytes += k.cloud.capacity() * sizeof(WeightedPoint);
  return bytes;
}

}  // namespace dlo
