// Helpers of the tests that compare vectorised kernels with their scalar references.
#pragma once

#include <Eigen/Geometry>
#include <cstring>
#include <random>
#include <vector>

namespace dlo::test {

/// The same bits: what "bit for bit" promises (0.0f and -0.0f differ, so do two NaNs with
/// different payloads).
inline bool sameBits(float a, float b) {
  return std::memcmp(&a, &b, sizeof(float)) == 0;
}

/// Lengths every kernel is tried at: none, one, around the vector widths (4 and 8) and the
/// unroll of sixteen, and an odd size of the order of a rasterisation batch.
inline std::vector<size_t> edgeLengths() {
  return {0, 1, 2, 3, 4, 5, 7, 8, 9, 15, 16, 17, 31, 33, 255, 256};
}

/// The poses the registration kernels are tried at: 0, the identity (a cell lands exactly where
/// it is); 1, a small turn about a tilted axis and a shift, like a registration's.
struct TestPose {
  Eigen::Matrix3f R;
  Eigen::Vector3f t;
};
inline TestPose testPose(int which) {
  if (which == 0) return {Eigen::Matrix3f::Identity(), Eigen::Vector3f::Zero()};
  return {
      Eigen::AngleAxisf(0.05f, Eigen::Vector3f(0.1f, 0.2f, 1.0f).normalized()).toRotationMatrix(),
      Eigen::Vector3f(0.13f, -0.07f, 0.02f)};
}

/// A generator with a fixed seed per test, so that a failure repeats.
inline std::mt19937 seeded(unsigned seed) {
  return std::mt19937(seed);
}

}  // namespace dlo::test
