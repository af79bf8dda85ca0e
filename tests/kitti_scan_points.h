/// \file kitti_scan_points.h
/// \brief Points of a real KITTI scan with reflectance, for test and fuzz-seed fixtures.
#pragma once

#include <mrpt/maps/CPointsMapXYZI.h>

#include <cstddef>
#include <limits>
#include <string>

#include "dlo/mrpt/kitti_conversion.h"

namespace dlo::test {

/// Every `step`-th point (from the first) of the KITTI scan at `path`, at most `max_points`,
/// with reflectance.
inline mrpt::maps::CPointsMapXYZI::Ptr kittiScanPoints(
    const std::string& path, size_t step, size_t max_points = std::numeric_limits<size_t>::max()) {
  mrpt::maps::CPointsMapXYZI full;
  loadKittiBinXYZI(path, full);
  auto out = mrpt::maps::CPointsMapXYZI::Create();
  for (size_t i = 0; i < full.size() && out->size() < max_points; i += step) {
    float x, y, z;
    full.getPointFast(i, x, y, z);
    out->insertPointFast(x, y, z);
    out->setPointIntensity(out->size() - 1, full.getPointIntensity(i));
  }
  out->mark_as_modified();
  return out;
}

}  // namespace dlo::test
