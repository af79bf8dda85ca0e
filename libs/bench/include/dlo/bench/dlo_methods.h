/// \file dlo_methods.h
/// \brief DLO as benchmarked: the paper's frame-to-frame odometry and the full SLAM pipeline.
#pragma once

#include "dlo/bench/odometry_method.h"
#include "dlo/slam/lidar_odometry.h"
#include "dlo/slam/slam_pipeline.h"

namespace dlo::bench {

/// The paper's DLO: every scan registered against the previous one (odometry.reference = 0),
/// no loop closure, through dlo::LidarOdometry (its own constant-velocity prediction and
/// deskewing).
class DloFrameToFrame : public OdometryMethod {
 public:
  /// `params` are used with odometry.reference forced to 0 and loop.enabled to 0.
  explicit DloFrameToFrame(SlamParams params = SlamParams());
  Eigen::Isometry3d process(double time, const PointCloud& points,
                            const std::vector<float>& point_times) override;

  /// The parameters as run.
  static SlamParams paperParams(SlamParams params);

 private:
  LidarOdometry odometry_;
};

/// The full pipeline (local-map odometry, keyframe graph, loop closure) with its defaults; the
/// reported trajectory is the optimised one at the end of the run.
class DloPipeline : public OdometryMethod {
 public:
  explicit DloPipeline(const SlamParams& params = SlamParams());
  Eigen::Isometry3d process(double time, const PointCloud& points,
                            const std::vector<float>& point_times) override;
  void finalise(metrics::Trajectory& trajectory) const override;

 private:
  SlamPipeline pipeline_;
};

}  // namespace dlo::bench
