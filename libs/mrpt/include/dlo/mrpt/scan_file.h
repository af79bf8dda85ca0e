/// \file scan_file.h
/// \brief Loading one scan from a file: KITTI .bin (plain or gzip), PLY, or an MRPT rawlog.
#pragma once

#include <string>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// The file formats loadScanFile() understands.
enum class ScanFormat { kKittiBin, kPly, kRawlog, kUnknown };

/// Format from the file name: `.bin`, `.bin.gz` (KITTI), `.ply`, `.rawlog`, `.rawlog.gz`.
ScanFormat scanFormatFromPath(const std::string& path);

/// Reads a KITTI Velodyne file (float32 x, y, z, reflectance; plain or gzip-compressed).
/// Non-finite points are dropped. Throws InputError if the file is missing or its size is not
/// a multiple of 16 bytes.
PointCloud loadKittiBin(const std::string& path, size_t* dropped_non_finite = nullptr);

/// Loads the scan in `path`: a KITTI file, a PLY file, or the first point-cloud-like
/// observation of a rawlog (read as a stream). Throws InputError with one sentence naming the
/// file if it is missing, of unknown format, unreadable, or holds no finite points.
PointCloud loadScanFile(const std::string& path);

}  // namespace dlo
