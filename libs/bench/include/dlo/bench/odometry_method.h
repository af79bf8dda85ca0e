/// \file odometry_method.h
/// \brief The interface every benchmarked odometry implements: scans in, poses out.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "dlo/core/point_cloud.h"
#include "dlo/metrics/trajectory.h"

namespace dlo::bench {

/// One odometry under test. The benchmark feeds every method the same scans in the same order
/// and times process() alone, so whatever a method does to the points (deskewing, cropping,
/// voxel filtering, building a search tree) counts as its processing.
class OdometryMethod {
 public:
  virtual ~OdometryMethod() = default;

  /// Processes the next scan.
  /// \param time seconds; increasing.
  /// \param points vehicle frame at `time`.
  /// \param point_times per-point seconds relative to `time`, or empty.
  /// \return the pose of the vehicle at `time` in the first scan's vehicle frame.
  virtual Eigen::Isometry3d process(double time, const PointCloud& points,
                                    const std::vector<float>& point_times) = 0;

  /// Replaces the poses returned by process() by the method's final estimate, for methods that
  /// revise the past (loop closure). The default keeps them.
  virtual void finalise(metrics::Trajectory& /*trajectory*/) const {}
};

}  // namespace dlo::bench
