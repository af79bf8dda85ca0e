/// \file dlo_methods.h
/// \brief DLO as benchmarked: the paper's frame-to-frame odometry and the full SLAM pipeline.
#pragma once

#include <optional>

#include "dlo/bench/odometry_method.h"
#include "dlo/slam/lidar_odometry.h"
#include "dlo/slam/slam_pipeline.h"

namespace dlo::bench {

/// The parameters of the sensor profile that dlo-slam would pick for a drive whose first scan is
/// `points` (dlo::chooseSensorProfile, with the points' origin taken as the sensor's: where it is
/// not, the rings blur and the point count decides).
SlamParams profileParams(const PointCloud& points);

/// The paper's DLO: every scan registered against the previous one (odometry.reference = previous),
/// no loop closure, through dlo::LidarOdometry (its own constant-velocity prediction and
/// deskewing).
class DloFrameToFrame : public OdometryMethod {
 public:
  /// With the sensor profile its first scan picks (profileParams()).
  DloFrameToFrame() = default;
  /// `params` are used with odometry.reference forced to 0 and loop.enabled to 0.
  explicit DloFrameToFrame(SlamParams params);
  Eigen::Isometry3d process(double time, const PointCloud& points,
                            const std::vector<float>& point_times) override;

  /// The parameters as run.
  static SlamParams paperParams(SlamParams params);

 private:
  std::optional<LidarOdometry> odometry_;  ///< made at the first scan without given params
};

/// The full pipeline (local-map odometry, keyframe graph, loop closure) with its defaults; the
/// reported trajectory is the optimised one at the end of the run.
class DloPipeline : public OdometryMethod {
 public:
  /// With the sensor profile its first scan picks (profileParams()).
  DloPipeline() = default;
  explicit DloPipeline(const SlamParams& params);
  Eigen::Isometry3d process(double time, const PointCloud& points,
                            const std::vector<float>& point_times) override;
  void finalise(metrics::Trajectory& trajectory) const override;

 private:
  std::optional<SlamPipeline> pipeline_;  ///< made at the first scan without given params
};

}  // namespace dlo::bench
