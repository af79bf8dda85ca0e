#include "dlo/bench/dlo_methods.h"

#include "dlo/slam/slam_report.h"

namespace dlo::bench {

SlamParams DloFrameToFrame::paperParams(SlamParams params) {
  params.odometry.reference = 0;
  params.loop.enabled = 0;
  return params;
}

DloFrameToFrame::DloFrameToFrame(SlamParams params) : odometry_(paperParams(std::move(params))) {}

Eigen::Isometry3d DloFrameToFrame::process(double time, const PointCloud& points,
                                           const std::vector<float>& point_times) {
  return odometry_.process(time, points, point_times).pose;
}

DloPipeline::DloPipeline(const SlamParams& params) : pipeline_(params) {}

Eigen::Isometry3d DloPipeline::process(double time, const PointCloud& points,
                                       const std::vector<float>& point_times) {
  pipeline_.process(time, points, point_times);
  const SlamMap& map = pipeline_.map();
  return map.framePose(map.frames.size() - 1);
}

void DloPipeline::finalise(metrics::Trajectory& trajectory) const {
  // Loop closures move past keyframes: the poses returned while running are only the
  // estimate as it was then.
  trajectory = slamTrajectory(pipeline_.map());
}

}  // namespace dlo::bench
