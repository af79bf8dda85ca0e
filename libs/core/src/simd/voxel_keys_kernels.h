/// \file voxel_keys_kernels.h
/// \brief The voxel keys of voxelise(), vectorised beside their scalar reference (internal to
/// dlo_core, not installed).
///
/// As in simd/height_grid_kernels.h: a kernel works on points [from, n) and returns where it
/// stopped; the scalar reference does them all. The SSE2 kernel gives the same keys
/// (tests/core/test_voxel_keys_kernels.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

namespace dlo::simd {

/// 21 bits per axis around the origin: +-1 M voxels, i.e. +-100 km at 0.1 m.
constexpr std::int32_t kAxisOffset = 1 << 20;
constexpr std::int32_t kAxisMax = (1 << 21) - 1;

/// A voxel coordinate: floor(v * inv_voxel) + kAxisOffset, clamped to [0, kAxisMax]. The
/// product is clamped first, to a range where the floor is exact in 32 bits (beyond it the
/// result is clamped anyway), as SSE's min and max do: a NaN becomes the upper bound (its
/// point is skipped; the conversion just has to be defined).
std::int32_t voxelAxis(float v, float inv_voxel);

/// The key of voxel (x, y, z), coordinates from voxelAxis().
inline std::uint64_t voxelKey(std::int32_t x, std::int32_t y, std::int32_t z) {
  return (static_cast<std::uint64_t>(x) << 42) | (static_cast<std::uint64_t>(y) << 21) |
         static_cast<std::uint64_t>(z);
}

/// The voxel keys of points (x[k], y[k], z[k]), k in [from, n), into keys[k]. Returns n.
size_t voxelKeysScalar(const float* x, const float* y, const float* z, size_t from, size_t n,
                       float inv_voxel, std::uint64_t* keys);

#ifdef __SSE2__
/// voxelKeysScalar(), four points at a time. std::floor is a library call on plain x86-64, and
/// the keys were the larger part of voxelisation.
size_t voxelKeysSse2(const float* x, const float* y, const float* z, size_t from, size_t n,
                     float inv_voxel, std::uint64_t* keys);
#endif

}  // namespace dlo::simd
