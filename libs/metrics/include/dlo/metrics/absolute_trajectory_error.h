/// \file absolute_trajectory_error.h
/// \brief ATE: position differences between an estimate and a reference after alignment.
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "dlo/metrics/error_statistics.h"
#include "dlo/metrics/trajectory.h"

namespace dlo::metrics {

/// How the estimate is brought into the reference frame before comparing positions.
enum class Alignment {
  kFirstPose,  ///< estimate moved so that its first pose equals the reference's first pose
  kUmeyama,    ///< SE(3) (rotation + translation, no scale) minimising the position RMSE
};

/// "first-pose" or "umeyama-se3", for reports.
std::string alignmentName(Alignment alignment);

/// Absolute trajectory error, metres.
struct AteResult {
  Alignment alignment = Alignment::kUmeyama;  ///< the alignment that was applied
  /// Transform applied to the estimate: aligned pose = transform * estimate pose.
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  ErrorStatistics error;  ///< of |p_ref - p_aligned| over all pose pairs
};

/// ATE of `estimate` against `reference`, which must be matched pose by pose (same length; see
/// matchedTrajectories()). Umeyama needs at least 3 non-collinear positions; with fewer it
/// falls back to the first-pose alignment, which is reported in AteResult::alignment.
/// \throws std::invalid_argument if the sizes differ or the trajectories are empty.
AteResult absoluteTrajectoryError(const Trajectory& estimate, const Trajectory& reference,
                                  Alignment alignment);

}  // namespace dlo::metrics
