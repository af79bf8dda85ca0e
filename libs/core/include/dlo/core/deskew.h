/// \file deskew.h
/// \brief Motion compensation of a rotating-LiDAR sweep with a constant-velocity model.
#pragma once

#include <vector>

#include "dlo/core/point_cloud.h"
#include "dlo/core/rigid_transform.h"

namespace dlo {

/// Expresses every point in the vehicle frame at the sweep's reference time (t = 0).
/// Point i was measured at `times[i]` seconds (relative to the reference) in the vehicle frame
/// of that instant; with a constant body twist `velocity` (per second: the motion between two
/// sweeps is expSE3(velocity * dt)) the vehicle pose at t relative to t = 0 is
/// expSE3(velocity * t), so the point is moved by it. Times are quantised to `bins` steps over
/// their range, which bounds the error to (speed * range / bins) while costing `bins` matrix
/// exponentials instead of one per point.
/// \return `points` unchanged if `times` is empty or of a different size.
PointCloud deskew(const PointCloud& points, const std::vector<float>& times,
                  const Vector6d& velocity, int bins = 128);

}  // namespace dlo
