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
  for (size_t k = 0; k < levels_.size(); ++k) {
    FrameLevel& level = levels_[k];
    Stopwatch sw;
    level.sampler = HeightSampler(level.grid.geometry(), computeGradients(level.grid));
    times_.gradients_ms += sw.elapsedMs();
    Stopwatch sel;
    // The suppression block keeps its size in metres: coarse levels have few cells to spare.
    SelectionParams at_level = selection;
    at_level.block_size = std::max(1, (selection.block_size + (1 << k) / 2) >> k);
    level.cells =
        selectHighGradientCells(level.grid, level.sampler.gradients(), at_level, include_ground);
    times_.selection_ms += sel.elapsedMs();
  }
}

}  // namespace dlo
