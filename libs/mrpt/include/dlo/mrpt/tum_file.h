/// \file tum_file.h
/// \brief Writing trajectories in the TUM RGB-D format read by evo and most SLAM tools.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace dlo {

/// Writes one line "t x y z qx qy qz qw" per pose (seconds, metres, unit quaternion) to `path`,
/// through a temporary file renamed at the end. `times` and `poses` have the same length.
/// \throws InputError naming the file if it cannot be written.
void writeTumTrajectory(const std::string& path, const std::vector<double>& times,
                        const std::vector<Eigen::Isometry3d>& poses);

}  // namespace dlo
