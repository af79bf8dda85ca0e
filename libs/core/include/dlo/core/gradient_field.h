/// \file gradient_field.h
/// \brief Spatial height gradients of a HeightGrid, computed on valid cells only.
#pragma once

#include <cstdint>
#include <vector>

#include "dlo/core/height_grid.h"

namespace dlo {

/// dH/dx and dH/dy in metres of height per metre, row-major like the grid. A cell's gradient is
/// valid only when the cell and its four neighbours have a height (measured or hole-filled): the
/// "edge" between a measured cell and an empty one is an artefact of sparsity, not of the world,
/// so it is masked.
struct GradientField {
  std::vector<float> gx;
  std::vector<float> gy;
  std::vector<std::uint8_t> valid;
  int cols = 0;
  int rows = 0;

  bool isValid(int row, int col) const { return valid[row * cols + col] != 0; }
  float magnitude(int row, int col) const;
};

/// Central differences on valid cells, masked next to empty cells.
GradientField computeGradients(const HeightGrid& grid);

}  // namespace dlo
