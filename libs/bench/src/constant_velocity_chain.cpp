#include "dlo/bench/constant_velocity_chain.h"

namespace dlo::bench {

Vector6d ConstantVelocityChain::velocity() const {
  if (scans_ < 2 || !(last_dt_ > 0.0)) return Vector6d::Zero();
  return logSE3(last_motion_) / last_dt_;
}

Eigen::Isometry3d ConstantVelocityChain::advance(double time, const Eigen::Isometry3d& motion) {
  if (scans_ > 0) {
    last_pose_ = last_pose_ * motion;
    last_motion_ = motion;
    last_dt_ = time - last_time_;
  }
  last_time_ = time;
  ++scans_;
  return last_pose_;
}

}  // namespace dlo::bench
