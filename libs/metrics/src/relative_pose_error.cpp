#include "dlo/metrics/relative_pose_error.h"

#include <cmath>
#include <stdexcept>

namespace dlo::metrics {

double rotationAngle(const Eigen::Matrix3d& R) {
  return Eigen::AngleAxisd(R).angle();
}

RpeResult relativePoseError(const Trajectory& estimate, const Trajectory& reference, size_t delta) {
  if (estimate.size() != reference.size() || delta == 0) {
    throw std::invalid_argument("RPE needs trajectories matched pose by pose and delta > 0.");
  }
  RpeResult result;
  result.delta = delta;
  std::vector<double> t_err, r_err;
  for (size_t i = 0; i + delta < estimate.size(); ++i) {
    const Eigen::Isometry3d est = estimate.poses[i].inverse() * estimate.poses[i + delta];
    const Eigen::Isometry3d ref = reference.poses[i].inverse() * reference.poses[i + delta];
    const Eigen::Isometry3d err = est.inverse() * ref;
    t_err.push_back(err.translation().norm());
    r_err.push_back(rotationAngle(err.rotation()) * 180.0 / M_PI);
  }
  result.translation = errorStatistics(std::move(t_err));
  result.rotation = errorStatistics(std::move(r_err));
  return result;
}

}  // namespace dlo::metrics
