#include "dlo/mrpt/height_grid_map_conversion.h"

namespace dlo {

HeightGrid toHeightGrid(const mrpt::maps::CHeightGridMap2D& map, int min_points) {
  GridGeometry geometry;
  geometry.x_min = map.getXMin();
  geometry.y_min = map.getYMin();
  geometry.resolution = map.getResolution();
  geometry.cols = static_cast<int>(map.getSizeX());
  geometry.rows = static_cast<int>(map.getSizeY());
  std::vector<float> heights(static_cast<size_t>(geometry.cellCount()));
  std::vector<std::uint32_t> counts(heights.size());
  // CDynamicGrid is row-major with y as the row, like HeightGrid.
  for (int r = 0; r < geometry.rows; ++r) {
    for (int c = 0; c < geometry.cols; ++c) {
      const mrpt::maps::THeightGridmapCell* cell = map.cellByIndex(c, r);
      const size_t i = static_cast<size_t>(r) * geometry.cols + c;
      heights[i] = cell->h;
      counts[i] = cell->w;
    }
  }
  return HeightGrid::fromCells(geometry, heights, counts, min_points);
}

}  // namespace dlo
