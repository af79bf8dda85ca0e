/// \file relative_pose_error.h
/// \brief RPE: error of the motion over a fixed number of frames (local drift).
#pragma once

#include "dlo/metrics/error_statistics.h"
#include "dlo/metrics/trajectory.h"

namespace dlo::metrics {

/// Relative pose error over `delta` frames.
struct RpeResult {
  size_t delta = 1;             ///< frames between the two poses of each pair
  ErrorStatistics translation;  ///< metres
  ErrorStatistics rotation;     ///< degrees
};

/// For every i, compares the estimated motion inv(E_i) E_{i+delta} with the reference motion
/// inv(R_i) R_{i+delta}: the error is inv(est motion) * ref motion, its translation norm and
/// rotation angle. Independent of any global alignment. Trajectories must be matched pose by
/// pose (see matchedTrajectories()).
/// \throws std::invalid_argument if sizes differ or delta is 0.
RpeResult relativePoseError(const Trajectory& estimate, const Trajectory& reference,
                            size_t delta = 1);

/// Rotation angle of a rotation matrix, radians (accurate near zero, unlike acos of the trace).
double rotationAngle(const Eigen::Matrix3d& R);

}  // namespace dlo::metrics
