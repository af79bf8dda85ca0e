/// \file estimate_evaluation.h
/// \brief All metrics of one estimated trajectory against ground truth: ATE, RPE, KITTI drift,
/// plus the aligned poses and per-frame errors the figures need.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "dlo/metrics/absolute_trajectory_error.h"
#include "dlo/metrics/kitti_drift.h"
#include "dlo/metrics/relative_pose_error.h"
#include "dlo/metrics/trajectory.h"

namespace dlo::eval {

/// How estimates are evaluated; one instance serves every estimate of a comparison.
struct EvaluationOptions {
  /// ATE alignment (SE(3) Umeyama: the usual choice, removes the arbitrary start frame).
  metrics::Alignment alignment = metrics::Alignment::kUmeyama;
  /// RPE pose distances, frames: 1 (frame-to-frame drift) and 10 (about a second at 10 Hz).
  std::vector<size_t> rpe_deltas = {1, 10};
  /// KITTI metric: the devkit's lengths, short-sequence fractions and start-frame step.
  metrics::KittiDriftParams kitti;
};

/// Fewest matched poses for which the metrics mean anything (Umeyama needs three).
constexpr size_t kMinMatchedPoses = 3;

/// An estimate paired pose by pose with ground truth, and how the pairs were made.
struct MatchedPair {
  metrics::Trajectory estimate;          ///< matched estimate poses
  metrics::Trajectory reference;         ///< ground-truth poses at the same indices
  std::vector<size_t> reference_frames;  ///< index in the full ground truth of each pair
  std::string method;                    ///< "timestamps" or "index"
};

/// Pairs each estimate pose with the ground-truth pose nearest in time (at most `max_dt` s
/// apart; see metrics::matchTimestamps()).
MatchedPair matchByTime(const metrics::Trajectory& estimate, const metrics::Trajectory& reference,
                        double max_dt);

/// Pairs estimate pose i with ground-truth pose i, as the KITTI devkit does for files without
/// timestamps. \throws std::invalid_argument if the estimate has more poses than the reference.
MatchedPair matchByIndex(const metrics::Trajectory& estimate, const metrics::Trajectory& reference);

/// Everything reported and plotted for one estimate.
struct EstimateEvaluation {
  size_t matched_poses = 0;
  std::string matching;                 ///< MatchedPair::method
  metrics::AteResult ate;               ///< ate.alignment is the alignment actually applied
  std::vector<metrics::RpeResult> rpe;  ///< one per EvaluationOptions::rpe_deltas
  metrics::KittiDriftResult kitti;
  metrics::Trajectory aligned;           ///< matched estimate after the ATE alignment
  std::vector<size_t> reference_frames;  ///< ground-truth frame of each matched pose
  std::vector<double> position_errors;   ///< |p_ref - p_aligned| per matched pose, metres
};

/// Computes every metric of `pair` (see MatchedPair).
/// \throws std::invalid_argument if fewer than kMinMatchedPoses poses are matched.
EstimateEvaluation evaluateEstimate(const MatchedPair& pair, const EvaluationOptions& options);

}  // namespace dlo::eval
