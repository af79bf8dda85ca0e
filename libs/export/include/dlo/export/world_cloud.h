/// \file world_cloud.h
/// \brief Keyframe clouds in the world frame: one at a time, or merged.
#pragma once

#include <functional>

#include "dlo/core/weighted_cloud.h"
#include "dlo/slam/slam_map.h"

namespace dlo {

/// Calls `visit` with every keyframe's cloud mapped by its pose into the world frame, in
/// keyframe order, one cloud in memory at a time (clouds in the map's spill file are read back
/// one by one), so that exporting a long run needs memory for one keyframe, not all of them.
void forEachWorldCloud(const SlamMap& map,
                       const std::function<void(const WeightedCloud& world_points)>& visit);

/// Every keyframe's cloud in the world frame, merged in voxels of side `voxel` metres (counts
/// add, centroids are weighted means), so overlapping keyframes do not multiply the points;
/// memory grows with the voxels, not the keyframes. `voxel` <= 0 concatenates without merging.
WeightedCloud worldCloud(const SlamMap& map, double voxel);

}  // namespace dlo
