// Helpers of the tests that compare vectorised kernels with their scalar references.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "dlo/core/cell_selection.h"
#include "dlo/core/grid_geometry.h"

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

/// Cells the registration kernels must treat like their references at the edges: a NaN, the
/// centres of the grid's first and last columns, and just inside the last, on the middle row.
inline std::vector<SelectedCell> edgeCells(const GridGeometry& g) {
  const float first = static_cast<float>(g.cellCentreX(0)),
              last = static_cast<float>(g.cellCentreX(g.cols - 1));
  const float middle = static_cast<float>(g.cellCentreY(g.rows / 2));
  std::vector<SelectedCell> out;
  for (float x : {std::numeric_limits<float>::quiet_NaN(), first, last, std::nextafter(last, 0.0f)})
    out.push_back(SelectedCell{x, middle, 0.5f, false});
  return out;
}

/// A generator with a fixed seed per test, so that a failure repeats.
inline std::mt19937 seeded(unsigned seed) {
  return std::mt19937(seed);
}

}  // namespace dlo::test
