/// \file ply_file.h
/// \brief Reading the vertices of a PLY file (ascii, binary little or big endian).
#pragma once

#include <string>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// The x, y, z of every vertex of the PLY file `path` (non-finite vertices are dropped). Other
/// elements and properties are skipped, whatever their order. Written instead of using MRPT's
/// reader, which crashes on truncated or malformed files and prints warnings for every optional
/// property (intensity, colour) a file lacks.
/// \throws InputError naming the file if it is missing, not a PLY file, has no vertex x, y, z, or
///         ends before all its vertices.
PointCloud loadPlyFile(const std::string& path);

}  // namespace dlo
