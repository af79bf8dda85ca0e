#include "dlo/core/cell_selection.h"

#include <algorithm>

namespace dlo {

std::vector<SelectedCell> selectHighGradientCells(const HeightGrid& grid,
                                                  const GradientField& gradients,
                                                  const SelectionParams& params,
                                                  bool include_ground) {
  std::vector<SelectedCell> cells;
  selectHighGradientCells(grid, gradients, params, include_ground, cells);
  return cells;
}

void selectHighGradientCells(const HeightGrid& grid, const GradientField& gradients,
                             const SelectionParams& params, bool include_ground,
                             std::vector<SelectedCell>& cells) {
  const GridGeometry& geo = grid.geometry();
  const int bs = std::max(1, params.block_size);
  const float min_sq = static_cast<float>(params.min_gradient * params.min_gradient);
  const std::vector<std::uint8_t>& measured = grid.validMask();
  cells.clear();
  cells.reserve(static_cast<size_t>(geo.cellCount() / (bs * bs) + 1));
  auto make_cell = [&](int r, int c) {
    return SelectedCell{static_cast<float>(geo.cellCentreX(c)),
                        static_cast<float>(geo.cellCentreY(r)), grid.height(r, c), false};
  };
  // The strongest gradient of each block: non-maximum suppression that spreads the selection
  // along edges instead of piling it on the few strongest walls. Blocks are scanned one band of
  // block rows at a time, keeping a running best per block column.
  const int block_cols = (geo.cols + bs - 1) / bs;
  std::vector<float> best(static_cast<size_t>(block_cols));
  std::vector<int> best_index(static_cast<size_t>(block_cols));
  for (int br = 0; br < geo.rows; br += bs) {
    std::fill(best.begin(), best.end(), min_sq);
    std::fill(best_index.begin(), best_index.end(), -1);
    for (int r = br; r < std::min(br + bs, geo.rows); ++r) {
      const GradientCell* g = &gradients.cells[r * geo.cols];
      const std::uint8_t* m = &measured[r * geo.cols];
      for (int c = 0; c < geo.cols; ++c) {
        const float mag = g[c].gx * g[c].gx + g[c].gy * g[c].gy;
        const int b = c / bs;
        if (m[c] && g[c].ok != 0.0f && mag >= best[b]) {
          best[b] = mag;
          best_index[b] = r * geo.cols + c;
        }
      }
    }
    for (int b = 0; b < block_cols; ++b) {
      if (best_index[b] >= 0)
        cells.push_back(make_cell(best_index[b] / geo.cols, best_index[b] % geo.cols));
    }
  }
  // Even thinning: keep every k-th cell in scan order (a fractional stride), which preserves the
  // spatial distribution, unlike keeping the strongest.
  const size_t cap = static_cast<size_t>(std::max(0, params.max_cells));
  if (cells.size() > cap) {
    // In place: the source index k * stride never falls behind k.
    const double stride = static_cast<double>(cells.size()) / static_cast<double>(cap);
    for (size_t k = 0; k < cap; ++k) cells[k] = cells[static_cast<size_t>(k * stride)];
    cells.resize(cap);
  }
  if (include_ground && params.ground_stride > 0) {
    const int s = params.ground_stride;
    for (int r = s / 2; r < geo.rows; r += s) {
      for (int c = s / 2; c < geo.cols; c += s) {
        if (!grid.isValid(r, c)) continue;
        SelectedCell cell = make_cell(r, c);
        cell.ground = true;
        cells.push_back(cell);
      }
    }
  }
}

}  // namespace dlo
