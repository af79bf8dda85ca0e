// The scalar references of HeightGrid's kernels (simd/height_grid_kernels.h): plain code that
// the vector kernels follow operation for operation, and that finishes what they leave.
#include <algorithm>

#include "simd/height_grid_kernels.h"

namespace dlo::simd {

CellMapping::CellMapping(const GridGeometry& geometry, double min_z, double max_z)
    : inv_res(static_cast<float>(1.0 / geometry.resolution)),
      x0(static_cast<float>(geometry.x_min)),
      y0(static_cast<float>(geometry.y_min)),
      cols(static_cast<float>(geometry.cols)),
      rows(static_cast<float>(geometry.rows)),
      zlo(static_cast<float>(min_z)),
      zhi(static_cast<float>(max_z)),
      grid_cols(geometry.cols),
      discard(geometry.cellCount()) {}

namespace {

/// One point.
void mapPoint(const CellMapping& c, const RowMajorPose& m, float px, float py, float pz, size_t k,
              int& idx, float& z, const CellFractions& f) {
  float x, y, h;
  m.apply(px, py, pz, x, y, h);
  const float u = (x - c.x0) * c.inv_res;
  const float v = (y - c.y0) * c.inv_res;
  // NaN fails every comparison; out-of-range floats are never converted to int.
  const bool inside =
      u >= 0.0f && u < c.cols && v >= 0.0f && v < c.rows && h >= c.zlo && h <= c.zhi;
  const int discard = c.discard + static_cast<int>(k % kDiscardCells);
  const int col = inside ? static_cast<int>(u) : 0;
  const int row = inside ? static_cast<int>(v) : 0;
  idx = inside ? row * c.grid_cols + col : discard;
  z = h;
  if (f.u != nullptr) {
    // Exact: u minus its integer part.
    f.u[k] = u - static_cast<float>(col);
    f.v[k] = v - static_cast<float>(row);
  }
}

}  // namespace

size_t mapPointsScalar(const CellMapping& cells, const Eigen::Vector3f* p, size_t from, size_t n,
                       const RowMajorPose& m, int* idx, float* z, CellFractions f) {
  for (size_t k = from; k < n; ++k) {
    mapPoint(cells, m, p[k].x(), p[k].y(), p[k].z(), k, idx[k], z[k], f);
  }
  return n;
}

size_t mapWeightedScalar(const CellMapping& cells, const WeightedPoint* p, size_t from, size_t n,
                         const RowMajorPose& m, int* idx, float* z, std::uint32_t* w,
                         CellFractions f) {
  for (size_t k = from; k < n; ++k) {
    mapPoint(cells, m, p[k].p.x(), p[k].p.y(), p[k].p.z(), k, idx[k], z[k], f);
    w[k] = p[k].n;
  }
  return n;
}

size_t binRunEndScalar(const int* bin, size_t k, size_t from, size_t n) {
  size_t end = from;
  while (end < n && bin[end] == bin[k]) ++end;
  return end;
}

void poolPairs(const std::uint32_t* __restrict__ cnt, const float* __restrict__ sum, int from,
               int n, const PoolRow& pool) {
  std::uint32_t* __restrict__ gc = pool.count;
  float* __restrict__ gs = pool.sum;
  const int pairs = n / 2;
  for (int j = from / 2; j < pairs; ++j) {
    gc[j] += cnt[2 * j] + cnt[2 * j + 1];
    gs[j] += sum[2 * j] + sum[2 * j + 1];
  }
  if (n % 2 != 0) {
    gc[pairs] += cnt[n - 1];
    gs[pairs] += sum[n - 1];
  }
}

int finaliseCellsScalar(const CellSums& cells, int from, int& valid_cells) {
  const std::int32_t* cnt = cells.count;
  if (cells.pool != nullptr) {
    poolPairs(reinterpret_cast<const std::uint32_t*>(cnt), cells.sum, from, cells.n, *cells.pool);
  }
  for (int i = from; i < cells.n; ++i) {
    const bool ok = cnt[i] >= cells.need;
    // "+ 0" turns a mean of -0 into 0.
    cells.height[i] = ok ? cells.sum[i] / static_cast<float>(cnt[i]) + 0.0f : 0.0f;
    cells.valid[i] = ok ? 1u : 0u;
    valid_cells += cells.valid[i];
  }
  return cells.n;
}

int pullColumnsScalar(const float* vs, const float* vh, int j, int j_end, float* value, float* ok) {
  for (; j < j_end; ++j) {
    const float we = 0.25f * vs[j] + 0.75f * vs[j + 1];
    const float wo = 0.75f * vs[j + 1] + 0.25f * vs[j + 2];
    value[2 * j] = (0.25f * vh[j] + 0.75f * vh[j + 1]) / std::max(we, 0.5f);
    value[2 * j + 1] = (0.75f * vh[j + 1] + 0.25f * vh[j + 2]) / std::max(wo, 0.5f);
    ok[2 * j] = we >= 0.5f ? 1.0f : 0.0f;
    ok[2 * j + 1] = wo >= 0.5f ? 1.0f : 0.0f;
  }
  return j_end;
}

}  // namespace dlo::simd
