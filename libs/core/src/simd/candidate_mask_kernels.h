/// \file candidate_mask_kernels.h
/// \brief The candidate test of selectHighGradientCells() (cell_selection.cpp), vectorised
/// beside its scalar reference (internal to dlo_core, not installed).
///
/// As in simd/height_grid_kernels.h: a kernel works on cells [from, n) and returns where it
/// stopped; the scalar reference does them all. The SSE2 kernel gives the same flags
/// (tests/core/test_candidate_mask_kernels.cpp).
#pragma once

#include <cstdint>

namespace dlo::simd {

/// mask[c] = 1 where the cell is measured (measured[c], 0 or 1) and its squared gradient
/// mag[c] is at least min_sq, else 0, for c in [from, n). Returns n.
int candidateMaskScalar(const float* mag, const std::uint8_t* measured, float min_sq, int from,
                        int n, std::uint8_t* mask);

#ifdef __SSE2__
/// candidateMaskScalar(), sixteen cells at a time; measured[] must hold 0 or 1 (the valid mask
/// of a HeightGrid), as the flags are and-ed with it.
int candidateMaskSse2(const float* mag, const std::uint8_t* measured, float min_sq, int from, int n,
                      std::uint8_t* mask);
#endif

}  // namespace dlo::simd
