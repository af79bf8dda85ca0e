#include "dlo/eval/estimate_evaluation.h"

#include <stdexcept>

#include "dlo/metrics/timestamp_matching.h"

namespace dlo::eval {

MatchedPair matchByTime(const metrics::Trajectory& estimate, const metrics::Trajectory& reference,
                        double max_dt) {
  MatchedPair pair;
  pair.method = "timestamps";
  for (const auto& [e, r] : metrics::matchTimestamps(estimate, reference, max_dt)) {
    pair.estimate.push_back(estimate.times[e], estimate.poses[e]);
    pair.reference.push_back(reference.times[r], reference.poses[r]);
    pair.reference_frames.push_back(r);
  }
  return pair;
}

MatchedPair matchByIndex(const metrics::Trajectory& estimate,
                         const metrics::Trajectory& reference) {
  if (estimate.size() > reference.size()) {
    throw std::invalid_argument("it holds " + std::to_string(estimate.size()) +
                                " poses but the ground truth only " +
                                std::to_string(reference.size()) + " (poses are paired by index)");
  }
  MatchedPair pair;
  pair.method = "index";
  pair.estimate = estimate;
  for (size_t i = 0; i < estimate.size(); ++i) {
    pair.reference.push_back(reference.times[i], reference.poses[i]);
    pair.reference_frames.push_back(i);
  }
  return pair;
}

EstimateEvaluation evaluateEstimate(const MatchedPair& pair, const EvaluationOptions& options) {
  const size_t n = pair.estimate.size();
  if (n < kMinMatchedPoses) {
    throw std::invalid_argument("only " + std::to_string(n) +
                                " of its poses match a ground-truth pose, at least " +
                                std::to_string(kMinMatchedPoses) + " are needed");
  }
  EstimateEvaluation result;
  result.matched_poses = n;
  result.matching = pair.method;
  result.reference_frames = pair.reference_frames;
  result.ate = metrics::absoluteTrajectoryError(pair.estimate, pair.reference, options.alignment);
  for (size_t delta : options.rpe_deltas) {
    result.rpe.push_back(metrics::relativePoseError(pair.estimate, pair.reference, delta));
  }
  result.kitti = metrics::kittiDrift(pair.estimate, pair.reference, options.kitti);
  result.aligned = pair.estimate;
  for (size_t i = 0; i < n; ++i) {
    result.aligned.poses[i] = result.ate.transform * pair.estimate.poses[i];
    result.position_errors.push_back(
        (pair.reference.poses[i].translation() - result.aligned.poses[i].translation()).norm());
  }
  return result;
}

}  // namespace dlo::eval
