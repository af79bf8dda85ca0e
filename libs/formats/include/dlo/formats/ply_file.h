/// \file ply_file.h
/// \brief Reading the vertices of a PLY file (ascii, binary little or big endian).
#pragma once

#include <istream>
#include <string>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// The x, y, z of every vertex of the PLY file `path` (vertices with a coordinate that is not
/// finite, or beyond float's range, are dropped). Other elements and properties are skipped,
/// whatever their order. Written instead of using MRPT's reader, which crashes on truncated or
/// malformed files and prints warnings for every optional property (intensity, colour) a file
/// lacks.
/// \throws InputError naming the file if it is missing, not a PLY file, has no vertex x, y, z, or
///         ends before all its vertices.
PointCloud loadPlyFile(const std::string& path);

/// Like loadPlyFile() on PLY bytes read from `in` (from its current position, opened in binary
/// mode): the reader behind loadPlyFile(), for data already in memory. `name` stands for the file
/// in error messages.
/// \throws InputError naming `name`, as loadPlyFile().
PointCloud loadPlyStream(std::istream& in, const std::string& name);

}  // namespace dlo
