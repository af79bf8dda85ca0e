/// \file rigid_transform.h
/// \brief SE(3) helpers: exponential map, yaw-pitch-roll conversions.
#pragma once

#include <Eigen/Geometry>

namespace dlo {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// exp of a twist (tx, ty, tz, wx, wy, wz) into a rigid transform (rotation vector w).
Eigen::Isometry3d expSE3(const Vector6d& xi);

/// log of a rigid transform: the twist (tx, ty, tz, wx, wy, wz) with expSE3(logSE3(T)) == T.
Vector6d logSE3(const Eigen::Isometry3d& T);

/// Rigid transform from MRPT-style parameters: R = Rz(yaw) Ry(pitch) Rx(roll), radians.
Eigen::Isometry3d poseFromXYZYPR(double x, double y, double z, double yaw, double pitch,
                                 double roll);

/// The (yaw, pitch, roll) of a rotation, R = Rz(yaw) Ry(pitch) Rx(roll), radians.
Eigen::Vector3d yawPitchRoll(const Eigen::Matrix3d& R);

}  // namespace dlo

namespace dlo {

/// Converts a covariance of a left-perturbation twist (x, y, z, wx, wy, wz) around `pose` into
/// the covariance of MRPT's pose parameters (x, y, z, yaw, pitch, roll), by linearisation.
Matrix6d twistCovarianceToXYZYPR(const Eigen::Isometry3d& pose, const Matrix6d& twist_cov);

}  // namespace dlo
