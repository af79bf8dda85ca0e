#include "dlo/bench/dlo_methods.h"

#include "dlo/slam/sensor_profile.h"
#include "dlo/slam/slam_report.h"

namespace dlo::bench {

SlamParams profileParams(const PointCloud& points) {
  const SensorEvidence e = sensorEvidence(points, 0, Eigen::Isometry3d::Identity());
  return resolveSlamParams(chooseSensorProfile(e).name, {});
}

SlamParams DloFrameToFrame::paperParams(SlamParams params) {
  params.odometry.reference = Reference::kPreviousScan;
  params.loop.enabled = false;
  return params;
}

DloFrameToFrame::DloFrameToFrame(SlamParams params)
    : odometry_(std::in_place, paperParams(std::move(params))) {}

Eigen::Isometry3d DloFrameToFrame::process(double time, const PointCloud& points,
                                           const std::vector<float>& point_times) {
  if (!odometry_) odometry_.emplace(paperParams(profileParams(points)));
  return odometry_->process(time, points, point_times).pose;
}

DloPipeline::DloPipeline(const SlamParams& params) : pipeline_(std::in_place, params) {}

Eigen::Isometry3d DloPipeline::process(double time, const PointCloud& points,
                                       const std::vector<float>& point_times) {
  if (!pipeline_) pipeline_.emplace(profileParams(points));
  pipeline_->process(time, points, point_times);
  const SlamMap& map = pipeline_->map();
  return map.framePose(map.frames.size() - 1);
}

void DloPipeline::finalise(metrics::Trajectory& trajectory) const {
  // Loop closures move past keyframes: the poses returned while running are only the
  // estimate as it was then.
  if (pipeline_) trajectory = slamTrajectory(pipeline_->map());
}

}  // namespace dlo::bench
