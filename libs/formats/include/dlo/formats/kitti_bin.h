/// \file kitti_bin.h
/// \brief Reading KITTI Velodyne `.bin` files (plain or gzip): 4 floats per point.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// The raw records of a KITTI Velodyne file: 4 floats per point (x, y, z in metres, sensor frame;
/// reflectance), non-finite values included. Reads plain or gzip-compressed files.
/// \throws InputError naming the file if it is missing, its gzip data is corrupt, or its
///         (decompressed) size is not a multiple of 16 bytes.
std::vector<float> readKittiBinRecords(const std::string& path);

/// Reads a KITTI Velodyne file (float32 x, y, z, reflectance; plain or gzip-compressed) as
/// points. Non-finite points are dropped (counted in `dropped_non_finite` when given).
/// \throws InputError as readKittiBinRecords().
PointCloud loadKittiBin(const std::string& path, size_t* dropped_non_finite = nullptr);

}  // namespace dlo
