#include "dlo/core/height_frame.h"

#include <algorithm>

namespace dlo {

HeightFrame HeightFrame::fromPoints(const PointCloud& points, const HeightGridParams& grid,
                                    const SelectionParams& selection, bool include_ground) {
  HeightFrame f;
  f.build(points, grid, selection, include_ground);
  return f;
}

HeightFrame HeightFrame::fromGrid(const HeightGrid& finest, int levels,
                                  const SelectionParams& selection, bool include_ground) {
  HeightFrame f;
  f.times_ = StageTimes();
  f.levels_.resize(static_cast<size_t>(std::max(1, levels)));
  f.levels_[0].grid = finest;
  f.buildLevels(selection, include_ground, FrameUse::kCurrentAndReference, false);
  return f;
}

void HeightFrame::build(const PointCloud& points, const HeightGridParams& grid,
                        const SelectionParams& selection, bool include_ground) {
  buildWith(
      [&](HeightGrid& finest, const GridGeometry& geometry, HeightGrid* coarser) {
        finest.rasterise(points, SweepMotion(), geometry, grid.min_points, grid.min_z, grid.max_z,
                         coarser);
      },
      grid, selection, include_ground);
}

void HeightFrame::build(const PointCloud& points, const SweepMotion& motion,
                        const HeightGridParams& grid, const SelectionParams& selection,
                        bool include_ground, FrameUse use) {
  buildWith(
      [&](HeightGrid& finest, const GridGeometry& geometry, HeightGrid* coarser) {
        finest.rasterise(points, motion, geometry, grid.min_points, grid.min_z, grid.max_z,
                         coarser);
      },
      grid, selection, include_ground, use);
}

void HeightFrame::build(const WeightedCloud& points, const Eigen::Isometry3d& pose,
                        const HeightGridParams& grid, const SelectionParams& selection,
                        bool include_ground) {
  build(std::vector<PosedCloud>{PosedCloud{&points, pose}}, grid, selection, include_ground);
}

void HeightFrame::build(const std::vector<PosedCloud>& parts, const HeightGridParams& grid,
                        const SelectionParams& selection, bool include_ground, FrameUse use) {
  buildWith(
      [&](HeightGrid& finest, const GridGeometry& geometry, HeightGrid* coarser) {
        finest.rasterise(parts, geometry, grid.min_points, grid.min_z, grid.max_z, coarser);
      },
      grid, selection, include_ground, use);
}

void HeightFrame::build(const HeightGrid::CellFiller& fill, const HeightGridParams& grid,
                        const SelectionParams& selection, bool include_ground, FrameUse use) {
  buildWith(
      [&](HeightGrid& finest, const GridGeometry& geometry, HeightGrid* coarser) {
        finest.accumulateCells(geometry, grid.min_points, fill, coarser);
      },
      grid, selection, include_ground, use);
}

void HeightFrame::buildWith(
    const std::function<void(HeightGrid&, const GridGeometry&, HeightGrid*)>& rasterise_finest,
    const HeightGridParams& grid, const SelectionParams& selection, bool include_ground,
    FrameUse use) {
  times_ = StageTimes();
  // resize() keeps the existing levels and their buffers: a frame rebuilt for every scan
  // reaches a steady state with no allocation at all.
  levels_.resize(static_cast<size_t>(std::max(1, grid.levels)));
  Stopwatch sw;
  // Level 1 is pooled while level 0 is finalised (one pass over level 0's sums, not two).
  HeightGrid* level1 = levels_.size() > 1 ? &levels_[1].grid : nullptr;
  rasterise_finest(levels_[0].grid, GridGeometry::centred(grid.cols, grid.rows, grid.resolution),
                   level1);
  times_.grid_ms = sw.elapsedMs();
  buildLevels(selection, include_ground, use, level1 != nullptr);
}

void HeightFrame::buildLevels(const SelectionParams& selection, bool include_ground, FrameUse use,
                              bool level1_pooled) {
  can_be_reference_ = use != FrameUse::kCurrentOnly;
  can_be_current_ = use != FrameUse::kReferenceOnly;
  // A current-only frame leaves its finest level unfilled: the selection pulls heights from
  // level 1 for the few cells next to measured ones that it needs.
  const size_t first_filled = can_be_reference_ ? 0 : 1;
  {
    Stopwatch sw;
    for (size_t k = level1_pooled ? 2 : 1; k < levels_.size(); ++k)
      levels_[k].grid.poolFrom(levels_[k - 1].grid);
    for (size_t k = levels_.size() - 1; k-- > first_filled;)
      levels_[k].grid.fillHolesFrom(levels_[k + 1].grid);
    times_.grid_ms += sw.elapsedMs();
  }
  for (size_t k = 0; k < levels_.size(); ++k) {
    FrameLevel& level = levels_[k];
    if (can_be_reference_) {
      Stopwatch sw;
      level.sampler.rebuild(level.grid);
      times_.gradients_ms += sw.elapsedMs();
    }
    if (!can_be_current_) {
      level.cells.clear();
      continue;
    }
    Stopwatch sel;
    // The suppression block keeps its size in metres: coarse levels have few cells to spare.
    SelectionParams at_level = selection;
    at_level.block_size = std::max(1, (selection.block_size + (1 << k) / 2) >> k);
    if (can_be_reference_) {
      selectHighGradientCells(level.grid, level.sampler.gradients(), at_level, include_ground,
                              level.cells);
    } else {
      // Gradients of measured cells only, computed by the selection itself.
      const HeightGrid* fill_source =
          k < first_filled && k + 1 < levels_.size() ? &levels_[k + 1].grid : nullptr;
      selectHighGradientCells(level.grid, fill_source, at_level, include_ground, level.cells);
    }
    times_.selection_ms += sel.elapsedMs();
  }
}

}  // namespace dlo
