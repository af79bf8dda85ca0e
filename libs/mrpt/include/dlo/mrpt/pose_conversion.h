/// \file pose_conversion.h
/// \brief mrpt::poses::CPose3D <-> Eigen::Isometry3d.
#pragma once

#include <mrpt/poses/CPose3D.h>
#include <Eigen/Geometry>

namespace dlo {

/// The rigid transform of an MRPT pose (R = Rz(yaw) Ry(pitch) Rx(roll), as dlo::poseFromXYZYPR).
Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& pose);

/// The MRPT pose of a rigid transform.
mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& pose);

}  // namespace dlo
