/// \file height_frame.h
/// \brief A scan prepared for registration: grid pyramid, gradients, samplers, selected cells.
#pragma once

#include <cstdint>

#include <functional>
#include <vector>

#include "dlo/core/cell_selection.h"
#include "dlo/core/gradient_field.h"
#include "dlo/core/height_grid.h"
#include "dlo/core/height_sampler.h"
#include "dlo/core/point_cloud.h"
#include "dlo/core/stage_times.h"

namespace dlo {

/// One pyramid level of a HeightFrame.
struct FrameLevel {
  HeightGrid grid;
  HeightSampler sampler;            ///< gradients; interpolated when this frame is the reference
  std::vector<SelectedCell> cells;  ///< used when this frame is the current scan
  /// Current scan: per selected cell, the centroid of its points minus the cell's centre (empty:
  /// not computed). Reference: per grid cell, row-major, the same offsets of its measured cells,
  /// zero where the height was filled (empty: not computed). See placeCellsOnCentroids().
  std::vector<Eigen::Vector2f> cell_offsets;
  std::vector<Eigen::Vector2f> grid_offsets;
};

/// What a frame is built for. A registration reads the selected cells of the current scan and
/// the samplers (gradient fields) of the reference. A scan that will never be a reference (the
/// local map is the reference) skips its samplers and the hole filling of its finest level,
/// which together cost more than its selection; its selected cells are the same either way. A
/// local map, only ever a reference, skips the selection.
enum class FrameUse {
  kCurrentAndReference,  ///< everything: the frame can be either side of a registration
  kCurrentOnly,          ///< selected cells only; the levels' samplers are left unset
  kReferenceOnly,        ///< samplers only; no cell is selected
};

/// Everything registration needs from one scan, computed once: a frame serves as the current
/// scan of one registration and as the reference of the next without recomputation.
/// levels[0] is the finest.
class HeightFrame {
 public:
  HeightFrame() = default;

  /// Builds the pyramid from points (grid frame, usually the vehicle frame).
  /// \param include_ground add low-gradient ground cells to the selection (6-DoF).
  static HeightFrame fromPoints(const PointCloud& points, const HeightGridParams& grid,
                                const SelectionParams& selection, bool include_ground);

  /// In-place form of fromPoints(): rebuilds this frame from new points, reusing its memory.
  /// Streaming code keeps a few frames and rebuilds them instead of allocating ~8 MB per scan.
  void build(const PointCloud& points, const HeightGridParams& grid,
             const SelectionParams& selection, bool include_ground);
  /// Rebuilds this frame from a sweep deskewed while it is rasterised (see
  /// HeightGrid::rasterise), for `use`.
  void build(const PointCloud& points, const SweepMotion& motion, const HeightGridParams& grid,
             const SelectionParams& selection, bool include_ground, FrameUse use);

  /// Rebuilds this frame from weighted points seen from `pose` (see HeightGrid::rasterise).
  void build(const WeightedCloud& points, const Eigen::Isometry3d& pose,
             const HeightGridParams& grid, const SelectionParams& selection, bool include_ground);
  /// Rebuilds this frame from several posed clouds fused into one grid.
  void build(const std::vector<PosedCloud>& parts, const HeightGridParams& grid,
             const SelectionParams& selection, bool include_ground,
             FrameUse use = FrameUse::kCurrentAndReference);

  /// Rebuilds this frame from cells accumulated elsewhere (see HeightGrid::accumulateCells()),
  /// in the centred geometry of `grid`, e.g. a LocalHeightMap window.
  void build(const HeightGrid::CellFiller& fill, const HeightGridParams& grid,
             const SelectionParams& selection, bool include_ground,
             FrameUse use = FrameUse::kCurrentAndReference);

  /// Builds the pyramid from an existing finest-level grid.
  static HeightFrame fromGrid(const HeightGrid& finest, int levels,
                              const SelectionParams& selection, bool include_ground);

  const std::vector<FrameLevel>& levels() const { return levels_; }
  /// HeightGrid::warmCaches() for every level.
  void warmCaches() const {
    for (const FrameLevel& level : levels_) level.grid.warmCaches();
  }
  bool empty() const { return levels_.empty() || levels_.front().grid.validCellCount() == 0; }
  /// False for a frame built FrameUse::kCurrentOnly: its samplers are not usable.
  bool canBeReference() const { return can_be_reference_; }
  /// False for a frame built FrameUse::kReferenceOnly: it has no selected cells.
  bool canBeCurrent() const { return can_be_current_; }
  /// Build time of this frame (grid, gradients, selection; solve_ms is zero).
  const StageTimes& buildTimes() const { return times_; }

 private:
  /// Level 0 by `rasterise_finest` (into the centred geometry of `grid`, pooling level 1 into
  /// its third argument when that is not null, keeping its centroid sums with `centroids`),
  /// then buildLevels().
  void buildWith(
      const std::function<void(HeightGrid&, const GridGeometry&, HeightGrid*)>& rasterise_finest,
      const HeightGridParams& grid, const SelectionParams& selection, bool include_ground,
      FrameUse use, bool centroids);
  /// Levels whose cells stand at their points' centroids: selection.centroid_levels, at most
  /// the grid's levels.
  static size_t centroidLevels(const HeightGridParams& grid, const SelectionParams& selection);
  /// The centroids of a frame whose level 0 kept its centroid sums: the offsets of every
  /// measured cell if the frame can be a reference (placeGrid()), of every selected cell if it
  /// can be the current scan (placeCellsOnCentroids()), on levels 0..n_levels-1.
  void placeOnCentroids(size_t n_levels);
  /// FrameLevel::grid_offsets of levels 0..n_levels-1 from level 0's centroid sums (nothing if
  /// it kept none); coarser levels pool them.
  void placeGrid(size_t n_levels);
  /// FrameLevel::cell_offsets of levels 0..n_levels-1: each selected cell's offset from its
  /// centre to the centroid of the points that made it. Where a scan samples a cell unevenly (a
  /// ring of a spinning sensor crossing a kerb's edge), the cell's mean height is measured where
  /// its points are, not at its centre: compared at the centre, it carries a bias that moves
  /// with the sensor and pulls registrations towards no motion.
  void placeCellsOnCentroids(size_t n_levels);
  /// Levels 1.. from level 0 (from 2 when `level1_pooled`: level 1 was made with level 0), hole
  /// filling, gradients and selection on every level.
  void buildLevels(const SelectionParams& selection, bool include_ground, FrameUse use,
                   bool level1_pooled);

  std::vector<FrameLevel> levels_;
  bool can_be_reference_ = true;
  bool can_be_current_ = true;
  StageTimes times_;
};

}  // namespace dlo
