// The scalar reference of selectHighGradientCells()'s candidate test
// (simd/candidate_mask_kernels.h).
#include "simd/candidate_mask_kernels.h"

namespace dlo::simd {

int candidateMaskScalar(const float* mag, const std::uint8_t* measured, float min_sq, int from,
                        int n, std::uint8_t* mask) {
  for (int c = from; c < n; ++c) mask[c] = measured[c] != 0 && mag[c] >= min_sq ? 1 : 0;
  return n;
}

}  // namespace dlo::simd
