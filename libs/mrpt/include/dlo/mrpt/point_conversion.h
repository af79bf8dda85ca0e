/// \file point_conversion.h
/// \brief Conversion of MRPT point maps to dlo::PointCloud.
#pragma once

#include <mrpt/maps/CPointsMap.h>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// Copies the points of an MRPT point map (non-finite points are dropped).
PointCloud toPointCloud(const mrpt::maps::CPointsMap& map);

}  // namespace dlo
