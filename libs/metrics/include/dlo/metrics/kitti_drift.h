/// \file kitti_drift.h
/// \brief The KITTI odometry metric: drift over sub-sequences of 100, 200, ..., 800 m.
#pragma once

#include <vector>

#include "dlo/metrics/trajectory.h"

namespace dlo::metrics {

/// Parameters of the KITTI drift metric.
struct KittiDriftParams {
  /// Sub-sequence lengths, metres (the devkit's). Lengths longer than the reference path are
  /// skipped; if none fits, `short_fractions` of the total length are used instead.
  std::vector<double> lengths = {100, 200, 300, 400, 500, 600, 700, 800};
  /// For paths shorter than the first length: fractions of the total path length.
  std::vector<double> short_fractions = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8};
  /// Start frames are 0, step, 2*step, ...: 10 as in the devkit (its figures are comparable);
  /// 1 uses every frame, which helps short sequences.
  size_t step = 10;
};

/// Drift of one sub-sequence length.
struct KittiLengthError {
  double length = 0.0;                 ///< metres
  size_t segments = 0;                 ///< sub-sequences evaluated
  double translation_percent = 0.0;    ///< mean translational error / length, %
  double rotation_deg_per_100m = 0.0;  ///< mean rotational error / length, deg per 100 m
};

/// Result of the KITTI metric.
struct KittiDriftResult {
  double translation_percent = 0.0;          ///< averaged over all segments of all lengths, %
  double rotation_deg_per_100m = 0.0;        ///< averaged over all segments, deg per 100 m
  size_t segments = 0;                       ///< total sub-sequences evaluated
  std::vector<KittiLengthError> per_length;  ///< only the lengths used (at least one segment)
  bool short_sequence = false;  ///< the lengths are fractions of the path (shorter than 100 m)
};

/// The KITTI devkit's evaluation: distances are measured along the reference path; for each
/// start frame (every `step`) and each length L, the end frame is the first whose distance
/// exceeds start + L; the error of the relative pose inv(inv(E_s) E_e) * inv(R_s) R_e gives a
/// translation norm / L and a rotation angle / L; all segments are averaged equally. Trajectories
/// must be matched pose by pose (see matchedTrajectories()).
/// \throws std::invalid_argument if sizes differ or step is 0.
KittiDriftResult kittiDrift(const Trajectory& estimate, const Trajectory& reference,
                            const KittiDriftParams& params = KittiDriftParams());

}  // namespace dlo::metrics
