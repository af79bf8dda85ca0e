/// \file simple_map_export.h
/// \brief Keyframes as an MRPT view-based map (CSimpleMap, `.simplemap`).
#pragma once

#include <mrpt/maps/CSimpleMap.h>
#include <string>

#include "dlo/slam/slam_map.h"

namespace dlo {

/// One entry per keyframe: a CPose3DPDFGaussian at the keyframe pose (covariance zero: the
/// graph's marginals are not computed) and a CSensoryFrame with one CObservationPointCloud
/// (sensor label "LIDAR") holding the keyframe's voxel centroids in the vehicle frame,
/// sensorPose identity, timestamp Keyframe::time.
mrpt::maps::CSimpleMap toSimpleMap(const SlamMap& map);

/// Writes toSimpleMap() with CSimpleMap::saveToFile (gz-compressed), atomically.
/// \throws OutputError naming `path`.
void exportSimpleMap(const SlamMap& map, const std::string& path);

}  // namespace dlo
