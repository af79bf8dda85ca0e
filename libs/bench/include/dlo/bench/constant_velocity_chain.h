/// \file constant_velocity_chain.h
/// \brief The benchmark's initial-guess policy for frame-to-frame registrators, and the chaining
/// of their relative motions into poses.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "dlo/core/rigid_transform.h"

namespace dlo::bench {

/// Chains frame-to-frame motions into poses (the first scan is the identity) and predicts the
/// next motion with constant velocity per frame: the guess for scan k is
/// pose_{k-1} * (pose_{k-2}^-1 pose_{k-1}), i.e. the last motion repeated. Every classic
/// registrator of the benchmark starts from this guess, so they differ only in registration.
class ConstantVelocityChain {
 public:
  /// Motion from the last scan to the next one as the policy predicts it (identity until two
  /// scans are chained).
  Eigen::Isometry3d predictedMotion() const { return last_motion_; }

  /// Body twist per second of the last motion (zero until two scans are chained), for deskewing
  /// the next scan with the same constant-velocity assumption.
  Vector6d velocity() const;

  /// Appends the scan at `time` whose pose relative to the previous scan is `motion` (ignored
  /// for the first scan). \return its pose in the first scan's frame.
  Eigen::Isometry3d advance(double time, const Eigen::Isometry3d& motion);

  /// Number of scans chained.
  size_t size() const { return scans_; }

 private:
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d last_motion_ = Eigen::Isometry3d::Identity();
  double last_time_ = 0.0;
  double last_dt_ = 0.0;
  size_t scans_ = 0;
};

}  // namespace dlo::bench
