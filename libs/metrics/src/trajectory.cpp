#include "dlo/metrics/trajectory.h"

namespace dlo::metrics {

std::vector<double> pathDistances(const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<double> d(poses.size(), 0.0);
  for (size_t i = 1; i < poses.size(); ++i) {
    d[i] = d[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  }
  return d;
}

}  // namespace dlo::metrics
