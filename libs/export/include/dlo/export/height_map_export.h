/// \file height_map_export.h
/// \brief The map as an MRPT 2.5D height grid (CHeightGridMap2D, `heightmap.bin`).
#pragma once

#include <mrpt/maps/CHeightGridMap2D.h>
#include <string>

#include "dlo/core/weighted_cloud.h"
#include "dlo/slam/slam_map.h"

namespace dlo {

/// A CHeightGridMap2D covering the x-y bounds of `world_points` plus `margin` metres, with cells
/// of `resolution` metres, each holding the mean height of the points in it as
/// CHeightGridMap2D::insertIndividualPoint() would: a weighted point (centroid of n points)
/// counts n times in the weight w, in the sum u and (as n points at the centroid) in the sum of
/// squares v, so h = u / w and later insertions continue the same running mean.
/// An empty cloud gives a single-cell map with no observed cell.
mrpt::maps::CHeightGridMap2D toHeightGridMap(const WeightedCloud& world_points, double resolution,
                                             double margin);

/// Serialises `grid` (usually toHeightGridMap() of worldCloud()) with
/// mrpt::io::CFileGZOutputStream and archiveFrom(...) << grid, atomically; read it back with
/// CFileGZInputStream and archiveFrom(...) >> grid.
/// \throws ExportError naming `path`.
void exportHeightGridMap(const mrpt::maps::CHeightGridMap2D& grid, const std::string& path);

}  // namespace dlo
