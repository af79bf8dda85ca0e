// Helpers shared by the tests: where the real samples live, and scan manipulation.
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "dlo/core/point_cloud.h"

namespace dlo::test {

/// Path of a file of ../shared/data.
inline std::string sharedData(const std::string& name) {
  return std::string(DLO_SHARED_DATA_DIR) + "/" + name;
}

/// Splits a scan into its even- and odd-indexed points: two disjoint clouds of one scene.
inline void splitEvenOdd(const PointCloud& scan, PointCloud& even, PointCloud& odd) {
  even.clear();
  odd.clear();
  for (size_t i = 0; i < scan.size(); ++i) (i % 2 == 0 ? even : odd).push_back(scan[i]);
}

/// Expresses `points` (given in frame A) in a frame B whose pose in A is `pose_b_in_a`:
/// p_B = pose^-1 p_A. Registering the result against A must recover `pose_b_in_a`.
inline PointCloud expressIn(const PointCloud& points, const Eigen::Isometry3d& pose_b_in_a) {
  const Eigen::Isometry3f inv = pose_b_in_a.inverse().cast<float>();
  PointCloud out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back(inv * p);
  return out;
}

}  // namespace dlo::test
