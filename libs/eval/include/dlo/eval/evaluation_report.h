/// \file evaluation_report.h
/// \brief The results of a comparison as metrics.json and as a compact text table.
#pragma once

#include <string>
#include <vector>

#include "dlo/eval/estimate_evaluation.h"

namespace dlo::eval {

/// One evaluated estimate with what identifies it in reports.
struct LabelledEvaluation {
  std::string label;  ///< name in tables and legends
  std::string file;   ///< the estimate's trajectory file
  size_t poses = 0;   ///< poses in the file (before matching)
  EstimateEvaluation evaluation;
};

/// What the estimates were compared against and how.
struct ComparisonSettings {
  std::string ground_truth_file;
  size_t ground_truth_poses = 0;
  double max_dt = 0.02;  ///< seconds, for estimates matched by timestamps
  EvaluationOptions options;
};

/// metrics.json: {"ground_truth": {...}, "settings": {...}, "estimates": [{label, file, poses,
/// matched_poses, matching, alignment, ate{rmse,mean,median,max}, rpe{"1_frames": {...}, ...},
/// kitti{translation_percent, rotation_deg_per_100m, segments, short_sequence, lengths[...],
/// per_length[...]}}, ...]}. Metres, degrees and percent, as the key names say.
std::string metricsJson(const ComparisonSettings& settings,
                        const std::vector<LabelledEvaluation>& estimates);

/// One line per estimate: matched poses, ATE RMSE and max, RPE translation and rotation for each
/// delta, KITTI drift; with a header naming units and the alignment, for a terminal.
std::string metricsTable(const ComparisonSettings& settings,
                         const std::vector<LabelledEvaluation>& estimates);

}  // namespace dlo::eval
