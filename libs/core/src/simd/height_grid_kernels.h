/// \file height_grid_kernels.h
/// \brief HeightGrid's vectorised kernels beside the scalar references they follow (internal to
/// dlo_core, not installed).
///
/// Every kernel has the signature of its scalar reference: it works on items [from, n) and
/// returns where it stopped. A scalar reference does them all (it returns n); a vector kernel
/// stops where fewer than a whole vector remain, and the caller finishes with the reference.
/// The kernels perform the reference's operations in the same order, lane by lane, with the
/// same types (no fused multiply-add), so that their results are the same bit for bit;
/// tests/core/test_height_grid_kernels.cpp compares them.
#pragma once

#include <cstddef>
#include <cstdint>

#include "dlo/core/deskew.h"
#include "dlo/core/grid_geometry.h"
#include "dlo/core/point_cloud.h"
#include "dlo/core/weighted_cloud.h"
#include "simd/cpu_features.h"

namespace dlo::simd {

/// Cells after the grid's own that rasterisation sends rejected points to: point k of a call
/// goes to number k % kDiscardCells (see CellMapping).
constexpr size_t kDiscardCells = 4;

/// What maps a point to its cell: the grid in floats. Points outside the grid or the height
/// band (NaN fails every comparison) go to discard cells after the grid's cells, so that the
/// scatter into cells has no branch on data: which points fall outside is as good as random
/// along a sweep (near and far rings interleave), and mispredicting it cost more than the rest
/// of the loop. There are kDiscardCells of them: with a single one, the sixth of an HDL-64
/// sweep beyond the grid made one chain of dependent additions to the same address.
struct CellMapping {
  CellMapping(const GridGeometry& geometry, double min_z, double max_z);
  float inv_res, x0, y0, cols, rows, zlo, zhi;
  int grid_cols;
  int discard;  ///< the first discard cell: geometry.cellCount()
};

/// Where in their cells mapped points fell: the fractions of a cell along columns (u) and rows
/// (v), in [0, 1) for points inside the grid (meaningless for the others). Either both
/// pointers are null (not wanted) or neither.
struct CellFractions {
  float* u = nullptr;
  float* v = nullptr;
};

/// Cell index and height of points p[from, n) mapped by `m`, into idx[k] and z[k], and where
/// in the cell they fell into f.u[k] and f.v[k] unless f's pointers are null. Returns n.
size_t mapPointsScalar(const CellMapping& cells, const Eigen::Vector3f* p, size_t from, size_t n,
                       const RowMajorPose& m, int* idx, float* z, CellFractions f = {});
/// The same for weighted points; their counts go to w[k].
size_t mapWeightedScalar(const CellMapping& cells, const WeightedPoint* p, size_t from, size_t n,
                         const RowMajorPose& m, int* idx, float* z, std::uint32_t* w,
                         CellFractions f = {});

/// Where the run of bins equal to bin[k] that continues at `from` ends: the first index in
/// [from, n) whose bin differs, or n.
size_t binRunEndScalar(const int* bin, size_t k, size_t from, size_t n);

/// Where a fine row's cells are pooled: the coarse row's counts and sums.
struct PoolRow {
  std::uint32_t* count;
  float* sum;
};

/// Adds cells [from, n) of a fine row (from even) into the coarse row, a pair of cells into
/// each coarse cell (c / 2), an odd last cell alone: the pooling of HeightGrid::poolFrom().
void poolPairs(const std::uint32_t* cnt, const float* sum, int from, int n, const PoolRow& pool);

/// n cells of counts and height sums, to finalise into heights and valid flags. Signed counts:
/// SSE2 converts and compares signed integers in one instruction, unsigned ones not (a cell
/// never holds 2^31 points).
struct CellSums {
  const std::int32_t* count;
  const float* sum;
  int n;
  std::int32_t need;  ///< points a cell needs to be valid, at least 1
  float* height;      ///< mean height where valid, else 0 (never -0)
  std::uint8_t* valid;
  const PoolRow* pool;  ///< or nullptr; else the cells are one fine row, pooled as poolPairs()
};
/// Heights and valid flags of cells [from, n) (from even), adding the number of valid ones to
/// valid_cells. Returns n.
int finaliseCellsScalar(const CellSums& cells, int from, int& valid_cells);

/// The horizontal half of the pull's interpolation for coarse columns [j, j_end): from the
/// vertical blends of support vs[] and of height vh[] (read up to j_end + 1), fine column 2j
/// lies 3/4 of the way from padded coarse column j to j + 1, column 2j + 1 1/4 of the way from
/// j + 1 to j + 2: value = blended height / max(blended support, 1/2) and ok = 1 where the
/// blended support is at least 1/2, else 0, at fine columns 2j and 2j + 1. Returns j_end.
int pullColumnsScalar(const float* vs, const float* vh, int j, int j_end, float* value, float* ok);

#ifdef __SSE2__
/// mapPointsScalar(), four points at a time. The compiler does not vectorise the scalar code by
/// itself: float compares may trap, which keeps it from if-converting them, and SSE2 has no
/// 32-bit integer multiply.
size_t mapPointsSse2(const CellMapping& cells, const Eigen::Vector3f* p, size_t from, size_t n,
                     const RowMajorPose& m, int* idx, float* z, CellFractions f = {});
/// mapWeightedScalar(), four points at a time.
size_t mapWeightedSse2(const CellMapping& cells, const WeightedPoint* p, size_t from, size_t n,
                       const RowMajorPose& m, int* idx, float* z, std::uint32_t* w,
                       CellFractions f = {});
/// binRunEndScalar(), four bins at a time (runs are hundreds of points long in firing order).
size_t binRunEndSse2(const int* bin, size_t k, size_t from, size_t n);
/// finaliseCellsScalar(), sixteen cells at a time.
int finaliseCellsSse2(const CellSums& cells, int from, int& valid_cells);
/// pullColumnsScalar(), four coarse columns (eight fine ones) at a time.
int pullColumnsSse2(const float* vs, const float* vh, int j, int j_end, float* value, float* ok);
#endif

#ifdef DLO_SIMD_AVX2_DISPATCH
/// mapPointsScalar(), eight points at a time; only where hasAvx2().
size_t mapPointsAvx2(const CellMapping& cells, const Eigen::Vector3f* p, size_t from, size_t n,
                     const RowMajorPose& m, int* idx, float* z, CellFractions f = {});
/// mapWeightedScalar(), eight points at a time; only where hasAvx2().
size_t mapWeightedAvx2(const CellMapping& cells, const WeightedPoint* p, size_t from, size_t n,
                       const RowMajorPose& m, int* idx, float* z, std::uint32_t* w,
                       CellFractions f = {});
#endif

}  // namespace dlo::simd
