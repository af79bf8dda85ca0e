/// \file deskew_kernels.h
/// \brief SweepMotion's vectorised kernels beside their scalar references (internal to
/// dlo_core, not installed).
///
/// As in simd/height_grid_kernels.h: a kernel works on items [from, n) and returns where it
/// stopped; the scalar reference does them all (tests/core/test_deskew_kernels.cpp).
#pragma once

#include <cstddef>

namespace dlo::simd {

/// Widens [lo, hi] to the times t[from, n), skipping NaN times (a NaN lo or hi stays NaN).
/// Returns n.
size_t widenTimeRangeScalar(const float* t, size_t from, size_t n, float& lo, float& hi);

/// How SweepMotion quantises a time: the nearest of bins 0..bins over [lo, lo + span].
struct TimeBins {
  float lo;
  float span;
  int bins;
};
/// SweepMotion::bin() of times t[from, n), into out[k]. Returns n.
size_t timeBinsScalar(const TimeBins& b, const float* t, size_t from, size_t n, int* out);

#ifdef __SSE2__
/// widenTimeRangeScalar(), four lanes at a time: the same smallest and largest value, though a
/// zero of the other sign may win when both +0 and -0 are among the extremes (each lane keeps
/// the first it met; the scan keeps the first of all). They compare equal and give the same
/// bins.
size_t widenTimeRangeSse2(const float* t, size_t from, size_t n, float& lo, float& hi);
/// timeBinsScalar(), four times at a time, for times in [lo, lo + span] (those the motion was
/// tabulated over) and NaN.
size_t timeBinsSse2(const TimeBins& b, const float* t, size_t from, size_t n, int* out);
#endif

}  // namespace dlo::simd
