#include "dlo/core/cell_selection.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "simd/candidate_mask_kernels.h"

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

/// The selection proper. `candidates(r)` gives row r's cells that may be selected: a byte per
/// column, non-zero at least at every measured cell whose squared gradient magnitude reaches
/// the threshold, zero at unmeasured ones; `magnitude(r, c)` gives the squared gradient
/// magnitude of such a cell, or -1 where the gradient is masked. Rows come in increasing
/// order, and magnitude() only for the row of the last candidates().
template <typename Candidates, typename Magnitude>
void select(const HeightGrid& grid, const SelectionParams& params, bool include_ground,
            std::vector<SelectedCell>& cells, Candidates candidates, Magnitude magnitude) {
  const GridGeometry& geo = grid.geometry();
  const int bs = std::max(1, params.block_size);
  const float min_sq = static_cast<float>(params.min_gradient * params.min_gradient);
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
  // Scratch kept across calls, used through plain pointers: a thread_local name (or a
  // reference to one) in the loop makes the compiler look up the thread's storage again at
  // every cell.
  thread_local std::vector<float> best_scratch;
  thread_local std::vector<int> index_scratch, block_scratch;
  best_scratch.resize(static_cast<size_t>(block_cols));
  index_scratch.resize(static_cast<size_t>(block_cols));
  block_scratch.resize(static_cast<size_t>(geo.cols));
  float* const best = best_scratch.data();
  int* const best_index = index_scratch.data();
  // The block column of each column: a table instead of a division per cell.
  int* const block_of = block_scratch.data();
  for (int c = 0; c < geo.cols; ++c) block_of[c] = c / bs;
  for (int br = 0; br < geo.rows; br += bs) {
    std::fill(best, best + block_cols, min_sq);
    std::fill(best_index, best_index + block_cols, -1);
    // Gradients need both neighbours: the first and last rows and columns have none.
    for (int r = std::max(br, 1); r < std::min(br + bs, geo.rows - 1); ++r) {
      forEachSet(candidates(r), geo.cols, [&](int c) {
        if (c == 0 || c == geo.cols - 1) return;
        const float mag = magnitude(r, c);  // -1 when masked: below any threshold
        const int b = block_of[c];
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
  const std::uint8_t* measured = grid.validMask().data();
  select(
      grid, params, include_ground, cells, [&](int r) { return measured + r * cols; },
      [&](int r, int c) {
        const GradientCell& g = gradients.cells[r * cols + c];
        return g.ok != 0.0f ? g.gx * g.gx + g.gy * g.gy : -1.0f;
      });
}

void selectHighGradientCells(const HeightGrid& grid, const HeightGrid* fill_source,
                             const SelectionParams& params, bool include_ground,
                             std::vector<SelectedCell>& cells) {
  if (fill_source != nullptr && !grid.isCoarserLevel(*fill_source)) {
    throw std::invalid_argument("selectHighGradientCells needs the grid's own coarser() level");
  }
  thread_local PullSource source_scratch;
  thread_local std::vector<float> row_scratch, rows_scratch;
  thread_local std::vector<std::uint8_t> mask_scratch;
  thread_local std::vector<std::uint64_t> chunk_scratch;
  PullSource& source = source_scratch;
  std::vector<float>& interpolation = row_scratch;
  if (fill_source != nullptr) fill_source->preparePull(source);
  const PullSource* pull = fill_source != nullptr ? &source : nullptr;
  // Heights and "has a height" flags of three consecutive rows, as fillHolesFrom(fill_source)
  // would leave them (row r in slot r % 3), the squared gradient magnitudes of the row being
  // selected and its candidates (measured cells at the threshold or above): computed in chunks
  // of columns, vectorised, and only around measured cells (at 0.1 m an HDL-64 scan has measured
  // cells in about a third of the chunks), so that the per-cell part of the selection only sees
  // the few cells on edges.
  const int cols = grid.cols();
  const size_t n = static_cast<size_t>(cols);
  // 16 columns (one SSE pass of the interpolation and the candidate mask), wider in grids of
  // more than 1024 columns, so that a row's chunks fit the bits of one 64-bit word.
  const int chunk = std::max(16, ((cols + 63) / 64 + 15) / 16 * 16);
  const int chunks = (cols + chunk - 1) / chunk;
  std::vector<float>& rows = rows_scratch;
  rows.resize(7 * n);
  float* height[3] = {rows.data(), rows.data() + n, rows.data() + 2 * n};
  float* has[3] = {rows.data() + 3 * n, rows.data() + 4 * n, rows.data() + 5 * n};
  float* const mag = rows.data() + 6 * n;
  std::vector<std::uint8_t>& mask_row = mask_scratch;
  mask_row.assign(n, 0);
  std::uint8_t* const mask = mask_row.data();
  // Chunks with measured cells, one bit each per row, and the chunks whose heights a row needs:
  // its own and its neighbours' (vertical differences) and one chunk either side of its own
  // (horizontal differences at the edges).
  const int rows_n = grid.rows();
  const std::uint8_t* measured = grid.validMask().data();
  std::vector<std::uint64_t>& own_scratch = chunk_scratch;
  own_scratch.assign(static_cast<size_t>(rows_n), 0);
  std::uint64_t* const own = own_scratch.data();
  const std::uint64_t all = chunks == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << chunks) - 1;
  for (int r = 0; r < rows_n; ++r) {
    const std::uint8_t* row = measured + r * n;
    std::uint64_t bits = 0;
    for (int ch = 0; ch < chunks; ++ch) {
      const int c0 = ch * chunk, c1 = std::min(cols, c0 + chunk);
      std::uint64_t word = 0;
      int c = c0;
      for (; c + 8 <= c1; c += 8) {
        std::uint64_t w;
        std::memcpy(&w, row + c, sizeof w);
        word |= w;
      }
      for (; c < c1; ++c) word |= row[c];
      if (word != 0) bits |= std::uint64_t{1} << ch;
    }
    // Without filling, a row's heights are a plain copy: whole rows cost less than chunks.
    own[r] = pull == nullptr && bits != 0 ? all : bits;
  }
  auto needed = [&](int r) {
    const std::uint64_t o = own[r];
    return (o | (o << 1) | (o >> 1) | (r > 0 ? own[r - 1] : 0) |
            (r + 1 < rows_n ? own[r + 1] : 0)) &
           all;
  };
  // Calls visit(first_chunk, end_chunk) for each run of set bits.
  auto forEachRun = [&](std::uint64_t bits, auto visit) {
    while (bits != 0) {
      const int a = __builtin_ctzll(bits);
      const std::uint64_t from_a = bits >> a;
      const int len = ~from_a == 0 ? 64 - a : __builtin_ctzll(~from_a);
      visit(a, a + len);
      bits = a + len >= 64 ? 0 : bits & (~std::uint64_t{0} << (a + len));
    }
  };
  int slot_row[3] = {-1, -1, -1};
  const float k = static_cast<float>(0.5 / grid.resolution());
  const float min_sq = static_cast<float>(params.min_gradient * params.min_gradient);
  // Row r's heights where it, or a row next to it, needs them, once per row.
  auto pulled = [&](int r) {
    const int s = r % 3;
    if (slot_row[s] != r) {
      forEachRun(needed(r), [&](int a, int b) {
        grid.pulledRow(r, pull, height[s], has[s], interpolation, a * chunk, b * chunk);
      });
      slot_row[s] = r;
    }
    return s;
  };
  auto candidates = [&](int r) {
    const std::uint8_t* row_measured = measured + r * n;
    if (own[r] == 0) return row_measured;
    const int d = pulled(r - 1), m = pulled(r), u = pulled(r + 1);
    const float* __restrict__ hd = height[d];
    const float* __restrict__ hm = height[m];
    const float* __restrict__ hu = height[u];
    const float* __restrict__ okd = has[d];
    const float* __restrict__ okm = has[m];
    const float* __restrict__ oku = has[u];
    float* __restrict__ out = mag;
    std::fill(mask, mask + n, 0);
    forEachRun(own[r], [&](int a, int b) {
      // Interior columns only: the first and last have no left or right neighbour.
      const int c0 = std::max(1, a * chunk), c1 = std::min(cols - 1, b * chunk);
      for (int c = c0; c < c1; ++c) {
        // computeGradients()'s central differences, in the same order of operations.
        const float gx = (hm[c + 1] - hm[c - 1]) * k;
        const float gy = (hu[c] - hd[c]) * k;
        // 1 where all four neighbours have a height, else 0; arithmetic rather than a
        // conditional, which the compiler does not vectorise (a float compare might trap).
        const float ok = okm[c - 1] * okm[c + 1] * okd[c] * oku[c];
        out[c] = ok * (gx * gx + gy * gy) + (ok - 1.0f);
      }
      // Candidates: measured interior cells at the threshold.
      int c = c0;
#ifdef __SSE2__
      c = simd::candidateMaskSse2(out, row_measured, min_sq, c, c1, mask);
#endif
      simd::candidateMaskScalar(out, row_measured, min_sq, c, c1, mask);
    });
    return static_cast<const std::uint8_t*>(mask);
  };
  select(grid, params, include_ground, cells, candidates, [&](int, int c) { return mag[c]; });
}

}  // namespace dlo
