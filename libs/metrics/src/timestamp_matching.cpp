#include "dlo/metrics/timestamp_matching.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dlo::metrics {

std::vector<std::pair<size_t, size_t>> matchTimestamps(const Trajectory& estimate,
                                                       const Trajectory& reference, double max_dt) {
  const std::vector<double>& ref = reference.times;
  if (ref.empty()) return {};
  // best[j]: the estimate index closest to reference pose j so far, and its distance.
  std::vector<size_t> best(ref.size(), std::numeric_limits<size_t>::max());
  std::vector<double> best_dt(ref.size(), std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < estimate.times.size(); ++i) {
    const double t = estimate.times[i];
    const auto it = std::lower_bound(ref.begin(), ref.end(), t);
    size_t j = static_cast<size_t>(it - ref.begin());
    // The nearest stamp is at j or j - 1.
    if (j == ref.size() || (j > 0 && std::abs(ref[j - 1] - t) <= std::abs(ref[j] - t))) --j;
    const double dt = std::abs(ref[j] - t);
    if (dt <= max_dt && dt < best_dt[j]) {
      best[j] = i;
      best_dt[j] = dt;
    }
  }
  std::vector<std::pair<size_t, size_t>> pairs;
  for (size_t j = 0; j < ref.size(); ++j) {
    if (best[j] != std::numeric_limits<size_t>::max()) pairs.emplace_back(best[j], j);
  }
  return pairs;
}

std::pair<Trajectory, Trajectory> matchedTrajectories(const Trajectory& estimate,
                                                      const Trajectory& reference, double max_dt) {
  std::pair<Trajectory, Trajectory> out;
  for (const auto& [i, j] : matchTimestamps(estimate, reference, max_dt)) {
    out.first.push_back(estimate.times[i], estimate.poses[i]);
    out.second.push_back(reference.times[j], reference.poses[j]);
  }
  return out;
}

}  // namespace dlo::metrics
