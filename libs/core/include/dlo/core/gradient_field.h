/// \file gradient_field.h
/// \brief Spatial height gradients of a HeightGrid, computed on supported cells only.
#pragma once

#include <cmath>
#include <vector>

#include "dlo/core/height_grid.h"

namespace dlo {

/// Height and gradient of one cell, interleaved so that a bilinear lookup touches two cache
/// lines. `ok` is 1 where the gradient is valid, 0 elsewhere (a float, to stay branch-friendly).
struct GradientCell {
  float h;   ///< height, metres
  float gx;  ///< dH/dx, metres of height per metre
  float gy;  ///< dH/dy, metres of height per metre
  float ok;  ///< 1 if valid
};

/// dH/dx and dH/dy, row-major like the grid. A cell's gradient is valid only when the cell and
/// its four neighbours have a height (measured or hole-filled): the "edge" between a measured
/// cell and an empty one is an artefact of sparsity, not of the world, so it is masked.
struct GradientField {
  int cols = 0;
  int rows = 0;
  std::vector<GradientCell> cells;

  const GradientCell& at(int row, int col) const { return cells[row * cols + col]; }
  bool isValid(int row, int col) const { return at(row, col).ok != 0.0f; }
  float magnitude(int row, int col) const {
    const GradientCell& c = at(row, col);
    return std::sqrt(c.gx * c.gx + c.gy * c.gy);
  }
};

/// Central differences on supported cells, masked next to empty cells.
GradientField computeGradients(const HeightGrid& grid);
/// In-place form of computeGradients(), reusing `out`'s memory.
void computeGradients(const HeightGrid& grid, GradientField& out);

}  // namespace dlo
