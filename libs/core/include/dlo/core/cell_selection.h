/// \file cell_selection.h
/// \brief Semi-dense selection of informative cells of a HeightGrid.
#pragma once

#include <vector>

#include "dlo/core/gradient_field.h"
#include "dlo/core/height_grid.h"

namespace dlo {

/// Parameters of the semi-dense selection (INI section [selection]).
struct SelectionParams {
  double min_gradient = 0.3;  ///< |grad H| threshold, metres of height per metre
  int block_size = 3;         ///< at most one gradient cell per block x block cells (even coverage)
  int max_cells = 6000;       ///< cap on gradient cells per level; thinned evenly beyond it
  int ground_stride = 6;      ///< 6-DoF only: also take every n-th valid cell (any gradient) to
                              ///< observe z, roll and pitch from the ground; 0 disables
  /// The finest levels whose cells stand at the centroids of their points, in the scan and in
  /// the reference alike (a cell's mean height is measured where its points are, not at its
  /// centre); 0: every cell at its centre (the paper, the default). See
  /// HeightFrame::placeCellsOnCentroids(); measured in docs/benchmarks.md.
  int centroid_levels = 0;
};

/// A selected cell: its centre in the grid frame and its mean height.
struct SelectedCell {
  float x = 0.0f;  ///< metres
  float y = 0.0f;  ///< metres
  float h = 0.0f;  ///< mean height, metres
  /// Selected from the ground lattice for z, roll and pitch only: its gradient is below the
  /// threshold, i.e. noise, so it must not pretend to constrain x, y or yaw.
  bool ground = false;
};

/// Picks cells whose gradient magnitude is at least `min_gradient`, keeping the strongest one in
/// each block of block_size x block_size cells, and thins the result evenly (deterministically)
/// down to `max_cells`. With `include_ground`, a regular lattice of valid low-gradient cells
/// (every `ground_stride` cells) is appended, so that z, roll and pitch are observable on flat
/// terrain.
std::vector<SelectedCell> selectHighGradientCells(const HeightGrid& grid,
                                                  const GradientField& gradients,
                                                  const SelectionParams& params,
                                                  bool include_ground);
/// In-place form of selectHighGradientCells(), reusing `out`'s memory.
void selectHighGradientCells(const HeightGrid& grid, const GradientField& gradients,
                             const SelectionParams& params, bool include_ground,
                             std::vector<SelectedCell>& out);
/// The same selection without a gradient field: gradients are computed from the grid's heights
/// at measured cells only. Neighbours without a height take the one fillHolesFrom(*fill_source)
/// would give them (HeightGrid::pulledRow), so the result equals filling the grid, computing
/// its gradients and calling the form above, at a fraction of the cost; the grid may also be
/// filled already. `fill_source` is the grid's coarser() level, hole-filled, or nullptr for no
/// filling; anything else throws std::invalid_argument.
void selectHighGradientCells(const HeightGrid& grid, const HeightGrid* fill_source,
                             const SelectionParams& params, bool include_ground,
                             std::vector<SelectedCell>& out);

}  // namespace dlo
