#include "dlo/metrics/absolute_trajectory_error.h"

#include <Eigen/Geometry>
#include <stdexcept>

namespace dlo::metrics {

namespace {

/// Umeyama is ill-posed when the positions lie on a line (rotation about it is free).
bool positionsSpanAPlane(const Eigen::Matrix3Xd& points) {
  if (points.cols() < 3) return false;
  const Eigen::Matrix3Xd centred = points.colwise() - points.rowwise().mean();
  const Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(centred);
  const Eigen::Vector3d s = svd.singularValues();
  return s(0) > 0.0 && s(1) > 1e-9 * s(0);
}

}  // namespace

std::string alignmentName(Alignment alignment) {
  return alignment == Alignment::kFirstPose ? "first-pose" : "umeyama-se3";
}

AteResult absoluteTrajectoryError(const Trajectory& estimate, const Trajectory& reference,
                                  Alignment alignment) {
  if (estimate.size() != reference.size() || estimate.empty()) {
    throw std::invalid_argument("ATE needs two non-empty trajectories matched pose by pose (" +
                                std::to_string(estimate.size()) + " and " +
                                std::to_string(reference.size()) + " poses given).");
  }
  const size_t n = estimate.size();
  Eigen::Matrix3Xd est(3, n), ref(3, n);
  for (size_t i = 0; i < n; ++i) {
    est.col(i) = estimate.poses[i].translation();
    ref.col(i) = reference.poses[i].translation();
  }
  AteResult result;
  result.alignment = alignment;
  if (alignment == Alignment::kUmeyama && !positionsSpanAPlane(est)) {
    result.alignment = Alignment::kFirstPose;
  }
  if (result.alignment == Alignment::kUmeyama) {
    result.transform.matrix() = Eigen::umeyama(est, ref, false);
  } else {
    result.transform = reference.poses.front() * estimate.poses.front().inverse();
  }
  std::vector<double> errors(n);
  for (size_t i = 0; i < n; ++i) {
    errors[i] = (ref.col(i) - result.transform * Eigen::Vector3d(est.col(i))).norm();
  }
  result.error = errorStatistics(std::move(errors));
  return result;
}

}  // namespace dlo::metrics
