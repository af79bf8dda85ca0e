/// \file world_cloud.h
/// \brief All keyframe clouds merged in the world frame.
#pragma once

#include "dlo/core/weighted_cloud.h"
#include "dlo/slam/slam_map.h"

namespace dlo {

/// Every keyframe's cloud mapped by its pose into the world frame and merged in voxels of side
/// `voxel` metres (counts add, centroids are weighted means), so overlapping keyframes do not
/// multiply the points. `voxel` <= 0 concatenates without merging.
WeightedCloud worldCloud(const SlamMap& map, double voxel);

}  // namespace dlo
