#include "dlo/core/height_frame.h"

#include <algorithm>

namespace dlo {

HeightFrame HeightFrame::fromPoints(const PointCloud& points, const HeightGridParams& grid,
                                    const SelectionParams& selection, bool include_ground) {
  HeightFrame f;
  Stopwatch sw;
  HeightGrid finest =
      HeightGrid::fromPoints(points, GridGeometry::centred(grid.cols, grid.rows, grid.resolution),
                             grid.min_points, grid.min_z, grid.max_z);
  f.times_.grid_ms = sw.elapsedMs();
  f.buildLevels(std::move(finest), grid.levels, selection, include_ground);
  return f;
}

HeightFrame HeightFrame::fromGrid(const HeightGrid& finest, int levels,
                                  const SelectionParams& selection, bool include_ground) {
  HeightFrame f;
  f.buildLevels(finest, levels, selection, include_ground);
  return f;
}

void HeightFrame::buildLevels(HeightGrid finest, int levels, const SelectionParams& selection,
                              bool include_ground) {
  levels_.clear();
  levels_.resize(static_cast<size_t>(std::max(1, levels)));
  levels_[0].grid = std::move(finest);
  {
    Stopwatch sw;
    for (size_t k = 1; k < levels_.size(); ++k) levels_[k].grid = levels_[k - 1].grid.coarser();
    for (size_t k = levels_.size() - 1; k-- > 0;) levels_[k].grid.fillHolesFrom(levels_[k + 1].grid);
    times_.grid_ms += sw.elapsedMs();
  }
  for (FrameLevel& level : levels_) {
    Stopwatch sw;
    level.gradients = computeGradients(level.grid);
    level.sampler = HeightSampler(level.grid, level.gradients);
    times_.gradients_ms += sw.elapsedMs();
    Stopwatch sel;
    level.cells = selectHighGradientCells(level.grid, level.gradients, selection, include_ground);
    times_.selection_ms += sel.elapsedMs();
  }
}

}  // namespace dlo
