#include "dlo/metrics/kitti_drift.h"

#include <cmath>
#include <stdexcept>

#include "dlo/metrics/relative_pose_error.h"

namespace dlo::metrics {

namespace {

/// The devkit's lastFrameFromSegmentLength: first frame beyond start + length, or -1.
long endFrame(const std::vector<double>& distances, size_t first, double length) {
  for (size_t i = first; i < distances.size(); ++i) {
    if (distances[i] > distances[first] + length) return static_cast<long>(i);
  }
  return -1;
}

}  // namespace

KittiDriftResult kittiDrift(const Trajectory& estimate, const Trajectory& reference,
                            const KittiDriftParams& params) {
  if (estimate.size() != reference.size() || params.step == 0) {
    throw std::invalid_argument(
        "the KITTI metric needs trajectories matched pose by pose and step > 0.");
  }
  KittiDriftResult result;
  const std::vector<double> distances = pathDistances(reference.poses);
  const double total = distances.empty() ? 0.0 : distances.back();

  std::vector<double> lengths;
  for (double l : params.lengths) {
    if (l < total) lengths.push_back(l);
  }
  if (lengths.empty()) {
    result.short_sequence = true;
    for (double f : params.short_fractions) lengths.push_back(f * total);
  }

  double t_sum = 0.0, r_sum = 0.0;
  for (double length : lengths) {
    if (!(length > 0.0)) continue;
    KittiLengthError le;
    le.length = length;
    double lt = 0.0, lr = 0.0;
    for (size_t first = 0; first < reference.size(); first += params.step) {
      const long last = endFrame(distances, first, length);
      if (last < 0) continue;
      const Eigen::Isometry3d ref = reference.poses[first].inverse() * reference.poses[last];
      const Eigen::Isometry3d est = estimate.poses[first].inverse() * estimate.poses[last];
      const Eigen::Isometry3d err = est.inverse() * ref;
      lt += err.translation().norm() / length;
      lr += rotationAngle(err.rotation()) / length;
      ++le.segments;
    }
    if (le.segments == 0) continue;
    t_sum += lt;
    r_sum += lr;
    result.segments += le.segments;
    le.translation_percent = 100.0 * lt / le.segments;
    le.rotation_deg_per_100m = 100.0 * 180.0 / M_PI * lr / le.segments;
    result.per_length.push_back(le);
  }
  if (result.segments > 0) {
    result.translation_percent = 100.0 * t_sum / result.segments;
    result.rotation_deg_per_100m = 100.0 * 180.0 / M_PI * r_sum / result.segments;
  }
  return result;
}

}  // namespace dlo::metrics
