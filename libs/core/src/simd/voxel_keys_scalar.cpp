// The scalar reference of voxelise()'s keys (simd/voxel_keys_kernels.h).
#include <algorithm>
#include <cmath>

#include "simd/voxel_keys_kernels.h"

namespace dlo::simd {

std::int32_t voxelAxis(float v, float inv_voxel) {
  constexpr float kHigh = 2.0f * kAxisOffset, kLow = -kAxisOffset - 1.0f;
  float t = v * inv_voxel;
  t = t < kHigh ? t : kHigh;
  t = t > kLow ? t : kLow;
  const std::int32_t i = static_cast<std::int32_t>(std::floor(t)) + kAxisOffset;
  return std::clamp(i, 0, kAxisMax);
}

size_t voxelKeysScalar(const float* x, const float* y, const float* z, size_t from, size_t n,
                       float inv_voxel, std::uint64_t* keys) {
  for (size_t k = from; k < n; ++k) {
    keys[k] = voxelKey(voxelAxis(x[k], inv_voxel), voxelAxis(y[k], inv_voxel),
                       voxelAxis(z[k], inv_voxel));
  }
  return n;
}

}  // namespace dlo::simd
