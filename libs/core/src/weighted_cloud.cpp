#include "dlo/core/weighted_cloud.h"

#include <algorithm>
#include <cmath>

namespace dlo {

namespace {

/// 21 bits per axis around the origin: +-1 M voxels, i.e. +-100 km at 0.1 m.
std::uint64_t voxelKey(const Eigen::Vector3f& p, float inv_voxel) {
  constexpr std::int64_t kOffset = 1 << 20;
  auto axis = [&](float v) {
    const std::int64_t i = static_cast<std::int64_t>(std::floor(v * inv_voxel)) + kOffset;
    return static_cast<std::uint64_t>(std::clamp<std::int64_t>(i, 0, (1 << 21) - 1));
  };
  return (axis(p.x()) << 42) | (axis(p.y()) << 21) | axis(p.z());
}

struct Keyed {
  std::uint64_t key;
  Eigen::Vector3f sum;
  std::uint32_t n;
};

/// Sort-based merge: no hash map, deterministic order, one allocation.
WeightedCloud mergeSorted(std::vector<Keyed>& items) {
  std::sort(items.begin(), items.end(),
            [](const Keyed& a, const Keyed& b) { return a.key < b.key; });
  WeightedCloud out;
  for (size_t i = 0; i < items.size();) {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    std::uint32_t n = 0;
    size_t j = i;
    for (; j < items.size() && items[j].key == items[i].key; ++j) {
      sum += items[j].sum;
      n += items[j].n;
    }
    out.push_back(WeightedPoint{sum / static_cast<float>(n), n});
    i = j;
  }
  return out;
}

}  // namespace

WeightedCloud voxelise(const PointCloud& points, double voxel) {
  const float inv = static_cast<float>(1.0 / voxel);
  std::vector<Keyed> items;
  items.reserve(points.size());
  for (const Eigen::Vector3f& p : points) {
    if (!p.allFinite()) continue;
    items.push_back(Keyed{voxelKey(p, inv), p, 1u});
  }
  return mergeSorted(items);
}

WeightedCloud voxelise(const WeightedCloud& points, double voxel) {
  const float inv = static_cast<float>(1.0 / voxel);
  std::vector<Keyed> items;
  items.reserve(points.size());
  for (const WeightedPoint& w : points) {
    if (w.n == 0 || !w.p.allFinite()) continue;
    items.push_back(Keyed{voxelKey(w.p, inv), w.p * static_cast<float>(w.n), w.n});
  }
  return mergeSorted(items);
}

WeightedCloud transformed(const WeightedCloud& cloud, const Eigen::Isometry3d& pose) {
  const Eigen::Isometry3f T = pose.cast<float>();
  WeightedCloud out(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) out[i] = WeightedPoint{T * cloud[i].p, cloud[i].n};
  return out;
}

std::uint64_t pointCount(const WeightedCloud& cloud) {
  std::uint64_t n = 0;
  for (const WeightedPoint& w : cloud) n += w.n;
  return n;
}

}  // namespace dlo
