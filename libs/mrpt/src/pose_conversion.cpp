#include "dlo/mrpt/pose_conversion.h"

#include "dlo/core/rigid_transform.h"

namespace dlo {

Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& pose) {
  return poseFromXYZYPR(pose.x(), pose.y(), pose.z(), pose.yaw(), pose.pitch(), pose.roll());
}

mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& pose) {
  // Through yaw/pitch/roll rather than the rotation matrix: CPose3D's matrix constructor does not
  // re-orthonormalise, and the angles are what MRPT stores anyway.
  const Eigen::Vector3d ypr = yawPitchRoll(pose.linear());
  const Eigen::Vector3d& t = pose.translation();
  return mrpt::poses::CPose3D(t.x(), t.y(), t.z(), ypr[0], ypr[1], ypr[2]);
}

}  // namespace dlo
