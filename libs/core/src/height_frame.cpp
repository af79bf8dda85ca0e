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
  build(points, SweepMotion(), grid, selection, include_ground, FrameUse::kCurrentAndReference);
}

void HeightFrame::build(const PointCloud& points, const SweepMotion& motion,
                        const HeightGridParams& grid, const SelectionParams& selection,
                        bool include_ground, FrameUse use) {
  buildWith(
      [&](HeightGrid& finest, const GridGeometry& geometry, HeightGrid* coarser) {
        finest.rasterise(points, motion, geometry, grid.min_points, grid.min_z, grid.max_z,
                         coarser);
      },
      grid, selection, include_ground, use, centroidLevels(grid, selection) > 0);
  placeOnCentroids(centroidLevels(grid, selection));
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
      grid, selection, include_ground, use,
      use != FrameUse::kCurrentOnly && centroidLevels(grid, selection) > 0);
  // Only the reference's side: posed clouds are keyframe maps, not scans.
  if (can_be_reference_) placeGrid(centroidLevels(grid, selection));
}

void HeightFrame::build(const HeightGrid::CellFiller& fill, const HeightGridParams& grid,
                        const SelectionParams& selection, bool include_ground, FrameUse use) {
  buildWith(
      [&](HeightGrid& finest, const GridGeometry& geometry, HeightGrid* coarser) {
        finest.accumulateCells(geometry, grid.min_points, fill, coarser);
      },
      grid, selection, include_ground, use, false);
}

void HeightFrame::buildWith(
    const std::function<void(HeightGrid&, const GridGeometry&, HeightGrid*)>& rasterise_finest,
    const HeightGridParams& grid, const SelectionParams& selection, bool include_ground,
    FrameUse use, bool centroids) {
  times_ = StageTimes();
  // resize() keeps the existing levels and their buffers: a frame rebuilt for every scan
  // reaches a steady state with no allocation at all.
  levels_.resize(static_cast<size_t>(std::max(1, grid.levels)));
  for (FrameLevel& level : levels_) {
    level.cell_offsets.clear();
    level.grid_offsets.clear();
  }
  Stopwatch sw;
  // Level 1 is pooled while level 0 is finalised (one pass over level 0's sums, not two).
  HeightGrid* level1 = levels_.size() > 1 ? &levels_[1].grid : nullptr;
  levels_[0].grid.keepCentroidSums(centroids);
  rasterise_finest(levels_[0].grid, GridGeometry::centred(grid.cols, grid.rows, grid.resolution),
                   level1);
  times_.grid_ms = sw.elapsedMs();
  buildLevels(selection, include_ground, use, level1 != nullptr);
}

size_t HeightFrame::centroidLevels(const HeightGridParams& grid, const SelectionParams& selection) {
  return static_cast<size_t>(
      std::min(std::max(1, grid.levels), std::max(0, selection.centroid_levels)));
}

void HeightFrame::placeOnCentroids(size_t n_levels) {
  if (n_levels == 0) return;
  if (can_be_reference_) placeGrid(n_levels);
  if (can_be_current_) {
    Stopwatch sw;
    placeCellsOnCentroids(n_levels);
    times_.selection_ms += sw.elapsedMs();
  }
}

void HeightFrame::placeGrid(size_t n_levels) {
  const HeightGrid& level0 = levels_[0].grid;
  if (n_levels == 0 || level0.centroidSums().empty()) return;
  Stopwatch sw;
  // Per cell of level k, the sums of where its points fell, in cells of level 0 from the
  // cell's corner, and of their weights: level 0's own sums (read in place), then pooled level
  // by level (a child's sums move by its corner's place in its parent). Scratch of the thread,
  // not of the frame: megabytes that every frame built as a reference (the keyframe map, a loop
  // closure's) would otherwise keep.
  thread_local std::vector<Eigen::Vector3f> sums_scratch, pooled_scratch;
  std::vector<Eigen::Vector3f>& sums = sums_scratch;  // along columns, along rows, weight
  std::vector<Eigen::Vector3f>& pooled = pooled_scratch;
  const GridGeometry& geo0 = level0.geometry();
  const float res0 = static_cast<float>(geo0.resolution);
  const std::vector<float>& uv = level0.centroidSums();
  const std::uint32_t* count0 = level0.counts().data();
  // Level 0's sums of cell i.
  const auto sums0 = [&](size_t i) {
    return Eigen::Vector3f(uv[2 * i], uv[2 * i + 1], static_cast<float>(count0[i]));
  };
  for (size_t k = 0; k < n_levels; ++k) {
    FrameLevel& level = levels_[k];
    const GridGeometry& geo = level.grid.geometry();
    const size_t cells = static_cast<size_t>(geo.cellCount());
    if (k > 0) {
      // The four children of each cell, added in row-major order as one pass over the finer
      // level would.
      const GridGeometry& fine = levels_[k - 1].grid.geometry();
      const float half = static_cast<float>(1 << (k - 1));  // a child's side, in level-0 cells
      pooled.resize(cells);
      for (int r = 0; r < geo.rows; ++r) {
        for (int c = 0; c < geo.cols; ++c) {
          Eigen::Vector3f p = Eigen::Vector3f::Zero();
          for (int dr = 0; dr < 2; ++dr) {
            const int fr = 2 * r + dr;
            if (fr >= fine.rows) break;
            const float dv = static_cast<float>(dr) * half;
            for (int dc = 0; dc < 2; ++dc) {
              const int fc = 2 * c + dc;
              if (fc >= fine.cols) break;
              const size_t j = static_cast<size_t>(fr * fine.cols + fc);
              const Eigen::Vector3f s = k == 1 ? sums0(j) : sums[j];
              const float du = static_cast<float>(dc) * half;
              p += Eigen::Vector3f(s.x() + s.z() * du, s.y() + s.z() * dv, s.z());
            }
          }
          pooled[static_cast<size_t>(r * geo.cols + c)] = p;
        }
      }
      sums.swap(pooled);
    }
    // Filled cells stay at their centres: their heights are interpolated there.
    level.grid_offsets.resize(cells);
    const float centre = 0.5f * static_cast<float>(1 << k);  // in level-0 cells
    const std::uint8_t* valid = level.grid.validMask().data();
    for (size_t i = 0; i < cells; ++i) {
      const Eigen::Vector3f s = k == 0 ? sums0(i) : sums[i];
      level.grid_offsets[i] =
          valid[i] == 0 || !(s.z() > 0.0f)
              ? Eigen::Vector2f::Zero()
              : Eigen::Vector2f(res0 * (s.x() / s.z() - centre), res0 * (s.y() / s.z() - centre));
    }
  }
  times_.gradients_ms += sw.elapsedMs();
}

void HeightFrame::placeCellsOnCentroids(size_t n_levels) {
  const HeightGrid& level0 = levels_[0].grid;
  const std::vector<float>& uv = level0.centroidSums();
  if (uv.empty()) return;
  const GridGeometry& geo0 = level0.geometry();
  for (size_t k = 0; k < n_levels && k < levels_.size(); ++k) {
    FrameLevel& level = levels_[k];
    const GridGeometry& geo = level.grid.geometry();
    const int side = 1 << k;
    level.cell_offsets.resize(level.cells.size());
    for (size_t i = 0; i < level.cells.size(); ++i) {
      const SelectedCell& cell = level.cells[i];
      // The level-0 cells of the selected cell: its points, wherever the selection put it.
      const int row = static_cast<int>(geo.v(cell.y)), col = static_cast<int>(geo.u(cell.x));
      double su = 0.0, sv = 0.0, n = 0.0;
      for (int r0 = row * side; r0 < std::min(geo0.rows, (row + 1) * side); ++r0) {
        for (int c0 = col * side; c0 < std::min(geo0.cols, (col + 1) * side); ++c0) {
          const size_t j = static_cast<size_t>(r0 * geo0.cols + c0);
          const double n0 = level0.count(r0, c0);
          su += n0 * c0 + uv[2 * j];
          sv += n0 * r0 + uv[2 * j + 1];
          n += n0;
        }
      }
      level.cell_offsets[i].setZero();
      if (n > 0.0) {
        level.cell_offsets[i] =
            Eigen::Vector2f(static_cast<float>(geo0.x_min + geo0.resolution * su / n - cell.x),
                            static_cast<float>(geo0.y_min + geo0.resolution * sv / n - cell.y));
      }
    }
  }
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
