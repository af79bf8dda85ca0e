/// \file sample_cells_kernels.h
/// \brief Where the Gauss-Newton linearisation (direct_aligner.cpp) samples the reference:
/// every selected cell moved into the reference and the reference's height and gradient there,
/// vectorised beside the scalar reference (internal to dlo_core, not installed).
///
/// As in simd/height_grid_kernels.h: a kernel works on cells [from, n) and returns where it
/// stopped; the scalar reference does them all. The SSE2 kernel performs the reference's
/// operations in its order, lane by lane, so that its results are the same bit for bit
/// (tests/core/test_sample_cells_kernels.cpp): the reads of the reference then overlap instead
/// of waiting behind the branches of each cell's residual.
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "dlo/core/cell_selection.h"
#include "dlo/core/gradient_field.h"
#include "dlo/core/height_sampler.h"

namespace dlo::simd {

/// Where a selected cell lands in the reference and what the reference holds there.
struct CellSample {
  GradientCell s;     ///< interpolated h, gx, gy; ok = 1 where the reference has them (where
                      ///< ok = 0, h, gx and gy are unspecified)
  Eigen::Vector3f q;  ///< cellInReference()
};

/// cellInReference(cells[k], R, t) and HeightSampler::sample() there, into out[k], for k in
/// [from, n). Returns n.
size_t sampleCellsScalar(const HeightSampler& sampler, const SelectedCell* cells, size_t from,
                         size_t n, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                         CellSample* out);

#ifdef __SSE2__
/// sampleCellsScalar(), four cells at a time.
size_t sampleCellsSse2(const HeightSampler& sampler, const SelectedCell* cells, size_t from,
                       size_t n, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                       CellSample* out);
#endif

}  // namespace dlo::simd
