/// \file point_cloud.h
/// \brief The point container the core works on.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace dlo {

/// A 3D point cloud in metres, in the frame of the vehicle or sensor that observed it
/// (x forward, y left, z up). Non-finite points are allowed and ignored by the rasteriser.
using PointCloud = std::vector<Eigen::Vector3f>;

}  // namespace dlo
