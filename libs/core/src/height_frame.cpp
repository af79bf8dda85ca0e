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
  placeOnPoints(points, SweepMotion(), grid, selection);
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
  placeOnPoints(points, motion, grid, selection);
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
  if (can_be_reference_ && centroidLevels(selection) > 0) {
    placeGrid(centroidLevels(selection),
              [&](std::vector<Eigen::Vector3d>& sums) { addCentroidSums(parts, grid, sums); });
  }
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
  for (FrameLevel& level : levels_) {
    level.cell_offsets.clear();
    level.grid_offsets.clear();
  }
  Stopwatch sw;
  // Level 1 is pooled while level 0 is finalised (one pass over level 0's sums, not two).
  HeightGrid* level1 = levels_.size() > 1 ? &levels_[1].grid : nullptr;
  rasterise_finest(levels_[0].grid, GridGeometry::centred(grid.cols, grid.rows, grid.resolution),
                   level1);
  times_.grid_ms = sw.elapsedMs();
  buildLevels(selection, include_ground, use, level1 != nullptr);
}

size_t HeightFrame::centroidLevels(const SelectionParams& selection) const {
  return std::min(levels_.size(), static_cast<size_t>(std::max(0, selection.centroid_levels)));
}

void HeightFrame::placeOnPoints(const PointCloud& points, const SweepMotion& motion,
                                const HeightGridParams& grid, const SelectionParams& selection) {
  const size_t n = centroidLevels(selection);
  if (n == 0) return;
  if (can_be_reference_) {
    placeGrid(n, [&](std::vector<Eigen::Vector3d>& sums) {
      const GridGeometry& finest = levels_[0].grid.geometry();
      mapSweepToCells(
          points, motion, finest, grid.min_z, grid.max_z,
          [&](const int* cells, const RowMajorPose* const* poses, size_t first, size_t count) {
            for (size_t j = 0; j < count; ++j) {
              if (cells[j] >= finest.cellCount()) continue;
              const Eigen::Vector3f q = *poses[j] * points[first + j];
              sums[static_cast<size_t>(cells[j])] += Eigen::Vector3d(q.x(), q.y(), 1.0);
            }
          });
    });
  }
  if (can_be_current_) {
    Stopwatch sw;
    placeCellsOnPoints(points, motion, grid, n);
    times_.selection_ms += sw.elapsedMs();
  }
}

void HeightFrame::addCentroidSums(const std::vector<PosedCloud>& parts,
                                  const HeightGridParams& grid,
                                  std::vector<Eigen::Vector3d>& sums) const {
  const GridGeometry& finest = levels_[0].grid.geometry();
  for (const PosedCloud& part : parts) {
    const RowMajorPose m(part.pose.cast<float>());
    mapWeightedToCells(*part.cloud, part.pose, finest, grid.min_z, grid.max_z,
                       [&](const int* cells, size_t first, size_t n) {
                         for (size_t j = 0; j < n; ++j) {
                           if (cells[j] >= finest.cellCount()) continue;
                           const WeightedPoint& w = (*part.cloud)[first + j];
                           const Eigen::Vector3f q = m * w.p;
                           const double n_w = static_cast<double>(w.n);
                           sums[static_cast<size_t>(cells[j])] +=
                               Eigen::Vector3d(n_w * q.x(), n_w * q.y(), n_w);
                         }
                       });
  }
}

void HeightFrame::placeGrid(size_t n_levels,
                            const std::function<void(std::vector<Eigen::Vector3d>&)>& add) {
  Stopwatch sw;
  // Sums of x, y and the weights per cell of level 0, then pooled level by level.
  // Scratch of the thread, not of the frame: megabytes that every frame built as a reference
  // (the keyframe map, a loop closure's) would otherwise keep.
  thread_local std::vector<Eigen::Vector3d> sums_scratch, pooled_scratch;
  std::vector<Eigen::Vector3d>& sums = sums_scratch;
  std::vector<Eigen::Vector3d>& pooled = pooled_scratch;
  sums.assign(static_cast<size_t>(levels_[0].grid.geometry().cellCount()), Eigen::Vector3d::Zero());
  add(sums);
  for (size_t k = 0; k < n_levels; ++k) {
    FrameLevel& level = levels_[k];
    const GridGeometry& geo = level.grid.geometry();
    if (k > 0) {
      const GridGeometry& fine = levels_[k - 1].grid.geometry();
      pooled.assign(static_cast<size_t>(geo.cellCount()), Eigen::Vector3d::Zero());
      for (int r = 0; r < fine.rows; ++r) {
        for (int c = 0; c < fine.cols; ++c) {
          pooled[static_cast<size_t>((r / 2) * geo.cols + c / 2)] +=
              sums[static_cast<size_t>(r * fine.cols + c)];
        }
      }
      sums.swap(pooled);
    }
    // Filled cells stay at their centres: their heights are interpolated there.
    level.grid_offsets.assign(static_cast<size_t>(geo.cellCount()), Eigen::Vector2f::Zero());
    for (int r = 0; r < geo.rows; ++r) {
      for (int c = 0; c < geo.cols; ++c) {
        const size_t i = static_cast<size_t>(r * geo.cols + c);
        if (!level.grid.isValid(r, c) || sums[i].z() <= 0.0) continue;
        level.grid_offsets[i] =
            Eigen::Vector2f(static_cast<float>(sums[i].x() / sums[i].z() - geo.cellCentreX(c)),
                            static_cast<float>(sums[i].y() / sums[i].z() - geo.cellCentreY(r)));
      }
    }
  }
  times_.gradients_ms += sw.elapsedMs();
}

void HeightFrame::placeCellsOnPoints(const PointCloud& points, const SweepMotion& motion,
                                     const HeightGridParams& grid, size_t n_levels) {
  slot_of_cell_.resize(n_levels);
  centroid_sums_.resize(n_levels);
  const auto cellOf = [](const GridGeometry& geo, const SelectedCell& cell) {
    return static_cast<size_t>(static_cast<int>(geo.v(cell.y)) * geo.cols +
                               static_cast<int>(geo.u(cell.x)));
  };
  // Per level, the selected cell of each grid cell; and a bit per cell of level 0, set where a
  // selected cell of any level covers it (small enough for the cache: most points fall in no
  // selected cell, and only those in one need their row and column).
  const GridGeometry& finest = levels_[0].grid.geometry();
  const int cells0 = finest.cellCount();
  const double inv_cols = 1.0 / finest.cols;
  std::vector<std::uint64_t>& covered = covered_bits_;
  covered.assign((static_cast<size_t>(cells0) + 63) / 64, 0);
  selected_bits_.resize(n_levels);
  for (size_t k = 0; k < n_levels; ++k) {
    const FrameLevel& level = levels_[k];
    const GridGeometry& geo = level.grid.geometry();
    const size_t cells = static_cast<size_t>(geo.cellCount());
    std::vector<int>& slots = slot_of_cell_[k];
    if (slots.size() != cells) slots.assign(cells, -1);
    selected_bits_[k].assign((cells + 63) / 64, 0);
    centroid_sums_[k].assign(level.cells.size(), Eigen::Vector3d::Zero());
    const int side = 1 << k;
    for (size_t i = 0; i < level.cells.size(); ++i) {
      const size_t c = cellOf(geo, level.cells[i]);
      slots[c] = static_cast<int>(i);
      selected_bits_[k][c / 64] |= std::uint64_t{1} << (c % 64);
      const int r = static_cast<int>(c) / geo.cols, col = static_cast<int>(c) % geo.cols;
      for (int r0 = r * side; r0 < std::min(finest.rows, (r + 1) * side); ++r0) {
        for (int c0 = col * side; c0 < std::min(finest.cols, (col + 1) * side); ++c0) {
          const size_t b = static_cast<size_t>(r0 * finest.cols + c0);
          covered[b / 64] |= std::uint64_t{1} << (b % 64);
        }
      }
    }
  }
  mapSweepToCells(points, motion, finest, grid.min_z, grid.max_z,
                  [&](const int* cells, const RowMajorPose* const* poses, size_t first, size_t n) {
                    for (size_t j = 0; j < n; ++j) {
                      const int cell = cells[j];
                      if (cell >= cells0) continue;
                      if (!(covered[static_cast<size_t>(cell) / 64] >> (cell % 64) & 1u)) continue;
                      // Row and column without an integer division (exact: cell + 0.5 stays half a
                      // column
                      // away from every multiple of the row length).
                      const int r0 = static_cast<int>((cell + 0.5) * inv_cols);
                      const int c0 = cell - r0 * finest.cols;
                      const Eigen::Vector3f q = *poses[j] * points[first + j];
                      for (size_t k = 0; k < n_levels; ++k) {
                        const size_t c = static_cast<size_t>(
                            (r0 >> k) * levels_[k].grid.geometry().cols + (c0 >> k));
                        if (!(selected_bits_[k][c / 64] >> (c % 64) & 1u)) continue;
                        const int slot = slot_of_cell_[k][c];
                        Eigen::Vector3d& sum = centroid_sums_[k][static_cast<size_t>(slot)];
                        sum.x() += q.x();
                        sum.y() += q.y();
                        sum.z() += 1.0;
                      }
                    }
                  });
  for (size_t k = 0; k < n_levels; ++k) {
    FrameLevel& level = levels_[k];
    const GridGeometry& geo = level.grid.geometry();
    level.cell_offsets.resize(level.cells.size());
    for (size_t i = 0; i < level.cells.size(); ++i) {
      const SelectedCell& cell = level.cells[i];
      slot_of_cell_[k][cellOf(geo, cell)] = -1;
      const Eigen::Vector3d& sum = centroid_sums_[k][i];
      level.cell_offsets[i].setZero();
      if (sum.z() > 0.0) {
        level.cell_offsets[i] = Eigen::Vector2f(static_cast<float>(sum.x() / sum.z() - cell.x),
                                                static_cast<float>(sum.y() / sum.z() - cell.y));
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
