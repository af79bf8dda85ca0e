/// \file bench_table.h
/// \brief The benchmark's result table: per method timing, accuracy against ground truth and
/// memory, as Markdown and CSV.
#pragma once

#include <string>
#include <vector>

#include "dlo/bench/method_run.h"
#include "dlo/metrics/trajectory.h"

namespace dlo::bench {

/// One line of the table. Accuracy fields are NaN when they cannot be computed (fewer than 3
/// poses matched to ground truth, a failed run).
struct MethodRow {
  std::string method;
  std::string preprocessing;
  size_t frames = 0;
  double ms_median = 0.0;      ///< per frame, processing only
  double ms_p95 = 0.0;         ///< per frame, processing only
  double frames_per_s = 0.0;   ///< frames / total processing time
  double ate_rmse = 0.0;       ///< metres, SE(3) Umeyama alignment
  double drift_percent = 0.0;  ///< KITTI translational drift
  std::string drift_lengths;   ///< segment lengths the drift averages, e.g. "100, 200 m"
  double peak_memory_mb = 0.0;
  std::string error;  ///< why the run or its evaluation failed, if it did
};

/// Timing, ATE (poses matched to `ground_truth` within 5 ms, SE(3) Umeyama) and KITTI drift of
/// the first `first_frames` poses of `run` (all if larger than the run). Without ground truth
/// (empty) the accuracy fields are NaN and no error is set.
MethodRow evaluateRun(const MethodRun& run, const std::string& preprocessing,
                      const metrics::Trajectory& ground_truth,
                      size_t first_frames = static_cast<size_t>(-1));

/// CSV with a header line: method, preprocessing, frames, ms_median, ms_p95, frames_per_s,
/// ate_m, drift_percent, peak_memory_mb (empty cells for unavailable numbers).
std::string tableCsv(const std::vector<MethodRow>& rows);

/// A Markdown table of `rows` (unavailable numbers shown as "n/a").
std::string tableMarkdown(const std::vector<MethodRow>& rows);

}  // namespace dlo::bench
