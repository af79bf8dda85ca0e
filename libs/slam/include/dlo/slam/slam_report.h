/// \file slam_report.h
/// \brief report.json of a dlo-slam run: timing, counters, memory, configuration, accuracy.
#pragma once

#include <optional>
#include <string>

#include "dlo/metrics/trajectory.h"
#include "dlo/slam/sensor_profile.h"
#include "dlo/slam/slam_pipeline.h"

namespace dlo {

/// Accuracy against ground truth, before (odometry only) and after loop closure.
struct SlamAccuracy {
  double ate_rmse_before = 0.0;  ///< metres, SE(3) Umeyama alignment
  double ate_rmse_after = 0.0;
  double ate_max_before = 0.0;
  double ate_max_after = 0.0;
  double drift_percent_before = 0.0;  ///< KITTI translational drift
  double drift_percent_after = 0.0;
  double drift_deg_per_100m_before = 0.0;  ///< KITTI rotational drift
  double drift_deg_per_100m_after = 0.0;
  std::string drift_lengths;        ///< the segment lengths used, e.g. "100..800 m" or "10%..80%"
  size_t matched = 0;               ///< estimate poses matched to ground truth by timestamp
  double final_error_before = 0.0;  ///< metres, position error of the last matched pose
  double final_error_after = 0.0;
};

/// The optimised and the odometry-only trajectories of a run.
metrics::Trajectory slamTrajectory(const SlamMap& map);
metrics::Trajectory odometryTrajectory(const SlamMap& map);

/// Compares both trajectories of `map` with `ground_truth` (timestamps matched within 5 ms).
/// \throws std::runtime_error if fewer than 3 poses match.
SlamAccuracy evaluateAgainst(const SlamMap& map, const metrics::Trajectory& ground_truth);

/// Everything report.json holds, as JSON text.
/// \param interrupted the run was stopped by a signal before the input ended.
std::string slamReportJson(const SlamPipeline& pipeline, const std::string& input,
                           const SensorProfileChoice& profile, const std::string& config_ini,
                           const std::optional<SlamAccuracy>& accuracy, bool interrupted,
                           const std::string& input_error);

}  // namespace dlo
