/// \file ply_export.h
/// \brief The point-cloud map as a binary PLY file.
#pragma once

#include <string>

#include "dlo/core/weighted_cloud.h"

namespace dlo {

/// Writes `points` (world frame) as a binary little-endian PLY with one vertex per point:
/// float x, y, z and uint count (the number of raw points the centroid stands for), atomically.
/// CloudCompare, MeshLab, Open3D and dlo::loadPlyFile read it.
/// \throws OutputError naming `path`.
void exportPly(const WeightedCloud& points, const std::string& path);

}  // namespace dlo
