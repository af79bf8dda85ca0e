/// \file height_map_image.h
/// \brief A top view of the height map with the trajectory and loop closures (`heightmap.png`).
#pragma once

#include <mrpt/maps/CHeightGridMap2D.h>
#include <opencv2/core/mat.hpp>

#include "dlo/slam/slam_map.h"

namespace dlo {

/// How the height map image looks.
struct HeightMapImageOptions {
  int min_side_px = 1000;         ///< small grids are enlarged (whole pixels per cell) up to this
  double low_percentile = 2.0;    ///< heights at or below this percentile get the first colour
  double high_percentile = 98.0;  ///< heights at or above this percentile get the last colour
};

/// Colour-coded mean heights (OpenCV TURBO colormap over the robust percentile range; empty cells
/// dark grey), +y up and +x right, with the frame trajectory (white polyline), keyframes (white
/// dots), accepted loop-closure edges (magenta lines between their keyframes), the height range,
/// a scale bar and the colour key in a legend. 8-bit BGR.
cv::Mat renderHeightMapImage(const mrpt::maps::CHeightGridMap2D& grid, const SlamMap& map,
                             const HeightMapImageOptions& options = HeightMapImageOptions());

}  // namespace dlo
