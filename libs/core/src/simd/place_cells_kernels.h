/// \file place_cells_kernels.h
/// \brief Where the Gauss-Newton iterations (direct_aligner.cpp, placed()) compare each selected
/// cell with a reference whose cells stand at their points' centroids: the place of the regular
/// lattice that the reference's centroid offsets take to the cell, by Newton's method,
/// vectorised beside the scalar reference (internal to dlo_core, not installed).
///
/// As in simd/sample_cells_kernels.h: a kernel works on cells [from, n) and returns where it
/// stopped; the scalar reference does them all. The SSE2 kernel performs the reference's
/// operations in its order, lane by lane (a lane that has converged keeps its place while the
/// others iterate), so that its results are the same bit for bit
/// (tests/core/test_place_cells_kernels.cpp).
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "dlo/core/cell_selection.h"
#include "dlo/core/grid_geometry.h"

namespace dlo::simd {

/// The reference's lattice of centroid offsets, as placeCells*() read it.
struct OffsetLattice {
  const Eigen::Vector2f* offsets = nullptr;  ///< rows x cols, row-major: centroid - centre
  int cols = 0;
  int rows = 0;
  float inv_res = 0.0f;  ///< cells per metre
  float x_c = 0.0f;      ///< centre of cell (0, 0), metres
  float y_c = 0.0f;
  float limit = 0.0f;  ///< longest Newton step, metres (half a cell)
};

/// The lattice of `offsets` (rows x cols of `geo`, row-major) in `geo`: coordinates in floats
/// from the centre of cell (0, 0), u = (x - x_c) / resolution; Newton steps of at most half a
/// cell.
inline OffsetLattice offsetLattice(const GridGeometry& geo, const Eigen::Vector2f* offsets) {
  OffsetLattice lattice;
  lattice.offsets = offsets;
  lattice.cols = geo.cols;
  lattice.rows = geo.rows;
  lattice.inv_res = static_cast<float>(1.0 / geo.resolution);
  lattice.x_c = static_cast<float>(geo.cellCentreX(0));
  lattice.y_c = static_cast<float>(geo.cellCentreY(0));
  lattice.limit = 0.5f * static_cast<float>(geo.resolution);
  return lattice;
}

/// Newton steps that place a cell from its own position (the first Gauss-Newton iteration of a
/// level) and from where it stood at the previous pose (`warm_start`). The pose moves little
/// between iterations, so that one step from there leaves an error of second order in that
/// motion (of first order for the few cells whose step crosses into the next lattice cell,
/// where the offsets' slope changes); it vanishes as the iterations converge
/// (tests/core/test_place_cells_kernels.cpp). A second step would mostly confirm the first.
constexpr int kColdNewtonSteps = 4;
constexpr int kWarmNewtonSteps = 1;

/// The offsets of the four cells from (r0, c0) to (r0 + 1, c0 + 1), zero beyond the lattice.
inline void cornerOffsets(const OffsetLattice& lattice, int r0, int c0, Eigen::Vector2f& d00,
                          Eigen::Vector2f& d10, Eigen::Vector2f& d01, Eigen::Vector2f& d11) {
  const int cols = lattice.cols, rows = lattice.rows;
  if (r0 >= 0 && c0 >= 0 && r0 + 1 < rows && c0 + 1 < cols) {
    const Eigen::Vector2f* o = lattice.offsets + static_cast<size_t>(r0 * cols + c0);
    d00 = o[0];
    d10 = o[1];
    d01 = o[cols];
    d11 = o[cols + 1];
    return;
  }
  const auto offset = [&](int r, int c) {
    return r < 0 || c < 0 || r >= rows || c >= cols
               ? Eigen::Vector2f::Zero()
               : lattice.offsets[static_cast<size_t>(r * cols + c)];
  };
  d00 = offset(r0, c0);
  d10 = offset(r0, c0 + 1);
  d01 = offset(r0 + 1, c0);
  d11 = offset(r0 + 1, c0 + 1);
}

/// For k in [from, n): cells[k] moved by cell_offsets[k] (to its centroid), taken into the
/// reference by (R, t), the place p of the lattice with p + offset(p) = its position solved for
/// (at most kWarmNewtonSteps Newton steps from its position - warm[k] where `warm_start`, else
/// at most kColdNewtonSteps from its position), and out[k] = the moved cell less R^T (position -
/// p). warm[k] = position - p where `warm` is not null. Returns n.
size_t placeCellsScalar(const OffsetLattice& lattice, const SelectedCell* cells,
                        const Eigen::Vector2f* cell_offsets, size_t from, size_t n,
                        const Eigen::Matrix3f& R, const Eigen::Vector3f& t, bool warm_start,
                        Eigen::Vector2f* warm, SelectedCell* out);

#ifdef __SSE2__
/// placeCellsScalar(), four cells at a time.
size_t placeCellsSse2(const OffsetLattice& lattice, const SelectedCell* cells,
                      const Eigen::Vector2f* cell_offsets, size_t from, size_t n,
                      const Eigen::Matrix3f& R, const Eigen::Vector3f& t, bool warm_start,
                      Eigen::Vector2f* warm, SelectedCell* out);
#endif

}  // namespace dlo::simd
