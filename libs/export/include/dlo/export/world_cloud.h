/// \file world_cloud.h
/// \brief Keyframe clouds in the world frame, one at a time.
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

}  // namespace dlo
