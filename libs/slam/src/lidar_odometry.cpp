#include "dlo/slam/lidar_odometry.h"

#include <cmath>

#include "dlo/core/deskew.h"

namespace dlo {

namespace {
constexpr double kDeg = M_PI / 180.0;

/// Points within `range` metres (horizontally) of the vehicle: what a keyframe keeps.
PointCloud withinRange(const PointCloud& points, double range) {
  PointCloud out;
  out.reserve(points.size());
  const float r2 = static_cast<float>(range * range);
  for (const Eigen::Vector3f& p : points) {
    if (p.head<2>().squaredNorm() <= r2) out.push_back(p);
  }
  return out;
}
}  // namespace

LidarOdometry::LidarOdometry(const SlamParams& params)
    : params_(params), aligner_(params.registration.solver) {}

OdometryStep LidarOdometry::process(double time, const PointCloud& points,
                                    const std::vector<float>& point_times) {
  OdometryStep step;
  const DloParams& reg = params_.registration;
  const double dt = frames_ == 0 ? 0.0 : time - last_time_;
  // Constant velocity: the motion of the last interval, repeated.
  const Eigen::Isometry3d predicted =
      dt > 0.0 && dt < 1.0 ? last_pose_ * expSE3(velocity_ * dt) : last_pose_;

  Stopwatch deskew_watch;
  const bool deskew = params_.odometry.deskew != 0 && !point_times.empty() && frames_ > 0;
  const PointCloud deskewed = deskew ? dlo::deskew(points, point_times, velocity_) : PointCloud();
  const PointCloud& cloud = deskew ? deskewed : points;
  step.times.deskew_ms = deskew_watch.elapsedMs();

  current_.build(cloud, reg.grid, reg.selection, reg.includeGround());
  step.times.registration = current_.buildTimes();

  Eigen::Isometry3d pose = predicted;
  if (has_reference_ && !current_.empty()) {
    step.registration = aligner_.align(reference_, current_, reference_pose_.inverse() * predicted);
    step.times.registration.solve_ms = step.registration.times.solve_ms;
    pose = reference_pose_ * step.registration.pose;
    step.registered = true;
  }
  step.pose = pose;

  if (frames_ > 0 && dt > 0.0 && dt < 1.0) velocity_ = logSE3(last_pose_.inverse() * pose) / dt;

  Stopwatch keyframe_watch;
  const bool first = frames_ == 0;
  if (!current_.empty() && (first || needsKeyframe(pose, step.registration))) {
    addKeyframe(pose, cloud, step);
  }
  if (params_.odometry.reference == 0 && !current_.empty()) {
    // Frame to frame, as in the paper: this scan is the next reference.
    std::swap(reference_, current_);
    reference_pose_ = pose;
    has_reference_ = true;
  }
  step.times.keyframe_ms = keyframe_watch.elapsedMs();

  last_pose_ = pose;
  last_time_ = time;
  ++frames_;
  return step;
}

bool LidarOdometry::needsKeyframe(const Eigen::Isometry3d& pose, const AlignmentResult& r) const {
  const Eigen::Isometry3d delta = last_keyframe_pose_.inverse() * pose;
  const OdometryParams& o = params_.odometry;
  if (delta.translation().norm() >= o.keyframe_distance) return true;
  if (Eigen::AngleAxisd(delta.linear()).angle() >= o.keyframe_angle * kDeg) return true;
  // A poor fit means the reference no longer describes the surroundings; a degenerate one
  // would make a poor keyframe, so it waits for structure to return.
  return !r.degenerate && r.rms_height_error > o.keyframe_max_rms;
}

void LidarOdometry::addKeyframe(const Eigen::Isometry3d& pose, const PointCloud& points,
                                OdometryStep& step) {
  const OdometryParams& o = params_.odometry;
  const PointCloud near = withinRange(points, o.map_range);
  const WeightedCloud fine = voxelise(near, o.keyframe_voxel);
  step.new_keyframe = true;
  step.keyframe_cloud = voxelise(fine, o.map_voxel);
  last_keyframe_pose_ = pose;
  if (o.reference == 0) return;
  recent_.push_back(RecentKeyframe{pose, fine});
  const size_t keep = o.reference == 1 ? 1 : static_cast<size_t>(o.local_map_keyframes);
  while (recent_.size() > keep) recent_.pop_front();
  rebuildLocalMap();
}

void LidarOdometry::rebuildLocalMap() {
  // All recent keyframes, expressed in the newest one's frame, in one grid: the mean height of
  // a cell then averages every keyframe that saw it.
  const DloParams& reg = params_.registration;
  const Eigen::Isometry3d& anchor = recent_.back().pose;
  WeightedCloud fused;
  for (const RecentKeyframe& k : recent_) {
    const WeightedCloud moved = transformed(k.cloud, anchor.inverse() * k.pose);
    fused.insert(fused.end(), moved.begin(), moved.end());
  }
  reference_.build(fused, Eigen::Isometry3d::Identity(), reg.grid, reg.selection,
                   reg.includeGround());
  reference_pose_ = anchor;
  has_reference_ = true;
}

}  // namespace dlo
