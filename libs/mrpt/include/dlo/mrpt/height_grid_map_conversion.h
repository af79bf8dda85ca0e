/// \file height_grid_map_conversion.h
/// \brief mrpt::maps::CHeightGridMap2D -> dlo::HeightGrid.
#pragma once

#include <mrpt/maps/CHeightGridMap2D.h>

#include "dlo/core/height_grid.h"

namespace dlo {

/// The grid of an MRPT height map: each cell's mean height `h` and point count `w`, with the
/// map's own origin, resolution and size. MRPT keeps the mean of every point inserted into a
/// cell, which is what HeightGrid holds too, so no information is lost.
/// \param min_points cells with fewer points (w) are invalid, as in HeightGridParams.
HeightGrid toHeightGrid(const mrpt::maps::CHeightGridMap2D& map, int min_points);

}  // namespace dlo
