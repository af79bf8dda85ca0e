/// \file point_conversion.h
/// \brief Conversions between MRPT point maps / observations and dlo::PointCloud.
#pragma once

#include <mrpt/maps/CPointsMap.h>
#include <mrpt/obs/CObservation.h>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// Copies the points of an MRPT point map (non-finite points are dropped).
PointCloud toPointCloud(const mrpt::maps::CPointsMap& map);

/// Points of a point-cloud-like observation in the vehicle frame (sensorPose applied).
/// Supports CObservationVelodyneScan (generatePointCloud() is called when needed),
/// CObservationPointCloud and CObservation3DRangeScan (with 3D points).
/// \return false if the observation is not of a supported class.
bool observationToPointCloud(const mrpt::obs::CObservation& obs, PointCloud& out);

}  // namespace dlo
