/// \file kitti_bin.h
/// \brief Reading KITTI Velodyne `.bin` files (plain or gzip) with their reflectance.
#pragma once

#include <mrpt/maps/CPointsMapXYZI.h>
#include <string>
#include <vector>

namespace dlo {

/// The raw records of a KITTI Velodyne file: 4 floats per point (x, y, z in metres, sensor frame;
/// reflectance), non-finite values included. Reads plain or gzip-compressed files.
/// \throws InputError naming the file if it is missing, its gzip data is corrupt, or its
///         (decompressed) size is not a multiple of 16 bytes.
std::vector<float> readKittiBinRecords(const std::string& path);

/// Loads a KITTI Velodyne file into `map` (replacing its contents) with reflectance as intensity.
/// Used instead of CPointsMapXYZI::loadFromKittiVelodyneFile, which neither reports why a file
/// is bad nor drops non-finite points. \return the number of non-finite points dropped.
/// \throws InputError as readKittiBinRecords().
size_t loadKittiBinXYZI(const std::string& path, mrpt::maps::CPointsMapXYZI& map);

}  // namespace dlo
