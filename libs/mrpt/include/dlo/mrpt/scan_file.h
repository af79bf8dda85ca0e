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

/// Loads the scan in `path`: a KITTI file (loadKittiBin()), a PLY file (loadPlyFile()), or the
/// first point-cloud-like observation of a rawlog (read as a stream). Throws InputError with one
/// sentence naming the file if it is missing, of unknown format, unreadable, or holds no finite
/// points.
PointCloud loadScanFile(const std::string& path);

}  // namespace dlo
