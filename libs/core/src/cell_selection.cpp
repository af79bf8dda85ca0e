#include "dlo/core/cell_selection.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace dlo {

namespace {

/// Calls visit(col) for every non-zero byte of mask[0, cols), in increasing order. Measured cells
/// are a few percent of a grid, so skipping empty words of eight cells at a time makes the
/// selection cost proportional to the measured cells instead of the grid.
template <typename Visit>
void forEachSet(const std::uint8_t* mask, int cols, Visit visit) {
  int c = 0;
  for (; c + 8 <= cols; c += 8) {
    std::uint64_t word;
    std::memcpy(&word, mask + c, sizeof word);
    while (word != 0) {
      const int bit = __builtin_ctzll(word);
      visit(c + bit / 8);
      word &= ~(std::uint64_t{0xFF} << (bit & ~7));
    }
  }
  for (; c < cols; ++c) {
    if (mask[c]) visit(c);
  }
}

/// The selection proper. `gradient(r, c, gx, gy)` gives the gradient of a measured interior
/// cell and returns false where it is masked; it is only asked for measured cells.
template <typename Gradient>
void select(const HeightGrid& grid, const SelectionParams& params, bool include_ground,
            std::vector<SelectedCell>& cells, Gradient gradient) {
  const GridGeometry& geo = grid.geometry();
  const int bs = std::max(1, params.block_size);
  const float min_sq = static_cast<float>(params.min_gradient * params.min_gradient);
  const std::uint8_t* measured = grid.validMask().data();
  cells.clear();
  cells.reserve(static_cast<size_t>(geo.cellCount() / (bs * bs) + 1));
  auto make_cell = [&](int r, int c) {
    return SelectedCell{static_cast<float>(geo.cellCentreX(c)),
                        static_cast<float>(geo.cellCentreY(r)), grid.height(r, c), false};
  };
  // The strongest gradient of each block: non-maximum suppression that spreads the selection
  // along edges instead of piling it on the few strongest walls. Blocks are scanned one band of
  // block rows at a time, keeping a running best per block column; within a band, cells come in
  // row-major order and a later cell wins a tie.
  const int block_cols = (geo.cols + bs - 1) / bs;
  // Scratch kept across calls; bound to references once, since every use of a thread_local
  // name in the loop would otherwise look up the thread's storage again.
  thread_local std::vector<float> best_scratch;
  thread_local std::vector<int> index_scratch;
  std::vector<float>& best = best_scratch;
  std::vector<int>& best_index = index_scratch;
  best.resize(static_cast<size_t>(block_cols));
  best_index.resize(static_cast<size_t>(block_cols));
  for (int br = 0; br < geo.rows; br += bs) {
    std::fill(best.begin(), best.end(), min_sq);
    std::fill(best_index.begin(), best_index.end(), -1);
    // Gradients need both neighbours: the first and last rows and columns have none.
    for (int r = std::max(br, 1); r < std::min(br + bs, geo.rows - 1); ++r) {
      forEachSet(measured + r * geo.cols, geo.cols, [&](int c) {
        float gx, gy;
        if (c == 0 || c == geo.cols - 1 || !gradient(r, c, gx, gy)) return;
        const float mag = gx * gx + gy * gy;
        const int b = c / bs;
        if (mag >= best[b]) {
          best[b] = mag;
          best_index[b] = r * geo.cols + c;
        }
      });
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

}  // namespace

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
  const int cols = grid.cols();
  select(grid, params, include_ground, cells, [&](int r, int c, float& gx, float& gy) {
    const GradientCell& g = gradients.cells[r * cols + c];
    gx = g.gx;
    gy = g.gy;
    return g.ok != 0.0f;
  });
}

void selectHighGradientCells(const HeightGrid& grid, const HeightGrid* fill_source,
                             const SelectionParams& params, bool include_ground,
                             std::vector<SelectedCell>& cells) {
  if (fill_source != nullptr && !grid.isCoarserLevel(*fill_source)) {
    throw std::invalid_argument("selectHighGradientCells needs the grid's own coarser() level");
  }
  thread_local PullSource source_scratch;
  PullSource& source = source_scratch;
  if (fill_source != nullptr) fill_source->preparePull(source);
  const int cols = grid.cols();
  const float k = static_cast<float>(0.5 / grid.resolution());
  const std::vector<float>& heights = grid.heights();
  const std::vector<std::uint8_t>& support = grid.supportMask();
  // A neighbour's height as computeGradients() would see it after fillHolesFrom(fill_source).
  auto height = [&](int r, int c, float& h) {
    const int i = r * cols + c;
    if (support[i]) {
      h = heights[i];
      return true;
    }
    return fill_source != nullptr && grid.pulledHeight(r, c, source, h);
  };
  select(grid, params, include_ground, cells, [&](int r, int c, float& gx, float& gy) {
    float left, right, down, up;
    if (!height(r, c - 1, left) || !height(r, c + 1, right) || !height(r - 1, c, down) ||
        !height(r + 1, c, up)) {
      return false;
    }
    // computeGradients()'s central differences, in the same order of operations.
    gx = (right - left) * k;
    gy = (up - down) * k;
    return true;
  });
}

}  // namespace dlo
