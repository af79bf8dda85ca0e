/// \file sweep_timing_kernels.h
/// \brief The per-point loop of estimateSweepTimes(), vectorised beside its scalar reference
/// (internal to dlo_core, not installed).
///
/// As in simd/height_grid_kernels.h: a kernel works on points [from, n) and returns where it
/// stopped; the scalar reference does them all. The SSE2 kernel performs the reference's
/// operations in the same order, lane by lane, so that the times are the same bit for bit
/// (tests/core/test_sweep_timing_kernels.cpp).
#pragma once

#include <cstddef>

#include "dlo/core/point_cloud.h"
#include "simd/cpu_features.h"

namespace dlo::simd {

/// How an azimuth becomes a time, from estimateSweepTimes().
struct SweepClock {
  float start;      ///< azimuth of the sweep's start, radians
  float dir;        ///< spin direction, +1 or -1
  float scale;      ///< seconds per radian of the sweep
  float offset;     ///< time of the sweep's start relative to the stamp, seconds
  float per_point;  ///< radians of sweep per point in firing order; 0 without an order
  bool ordered;     ///< the cloud is in firing order: a point's place picks its revolution
};

/// atan2(y, x) in [-pi, pi] within 2e-5 rad, with no branch and no library call.
float fastAtan2(float y, float x);

/// The time of points p[from, n) into times[k]: the azimuth travelled from the start in the
/// spin direction, in [0, 2 pi) (the revolution nearest the point's place in an ordered cloud),
/// times scale, plus offset; 0 for a non-finite point. Returns n.
size_t sweepTimesScalar(const SweepClock& clock, const Eigen::Vector3f* p, size_t from, size_t n,
                        float* times);

#ifdef __SSE2__
/// sweepTimesScalar(), four points at a time, bit for bit for finite points, infinite ones and
/// NaN points (x and y NaN). A point with only one of x, y NaN is timed differently: MAXPS and
/// MINPS return their second operand where std::max and std::min return their first, so the
/// kernel gives such a point a finite time and the reference 0. No caller passes one (the
/// readers drop non-finite points), and the kernel is kept as it was so that results do not
/// change.
size_t sweepTimesSse2(const SweepClock& clock, const Eigen::Vector3f* p, size_t from, size_t n,
                      float* times);
#endif

#ifdef DLO_SIMD_AVX2_DISPATCH
/// sweepTimesSse2(), eight points at a time, bit for bit with it (the same operations lane by
/// lane); only where hasAvx2(). Returns where it stopped (a multiple of 8 after `from`).
size_t sweepTimesAvx2(const SweepClock& clock, const Eigen::Vector3f* p, size_t from, size_t n,
                      float* times);
#endif

}  // namespace dlo::simd
