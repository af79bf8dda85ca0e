// Helpers of the input tests: temporary folders and small rawlogs built from the real KITTI scan.
#pragma once

#include <gtest/gtest.h>

#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/serialization/CArchive.h>
#include <filesystem>
#include <string>

#include "../kitti_scan_points.h"
#include "../temp_dir.h"
#include "../test_data.h"

namespace dlo::test {

/// Every `step`-th point of the real HDL-64 scan (with reflectance): small enough for quick
/// rawlog round trips, still real structure.
inline mrpt::maps::CPointsMapXYZI::Ptr kittiSubsample(size_t step) {
  return kittiScanPoints(sharedData("kitti_00_000000.bin.gz"), step);
}

/// A CObservationPointCloud holding `map` (shared), with a label and a timestamp in seconds.
inline mrpt::obs::CObservationPointCloud::Ptr pointCloudObservation(
    const mrpt::maps::CPointsMap::Ptr& map, const std::string& label, double t) {
  auto obs = mrpt::obs::CObservationPointCloud::Create();
  obs->pointcloud = map;
  obs->sensorLabel = label;
  obs->timestamp = mrpt::Clock::fromDouble(t);
  return obs;
}

/// Writes serializable objects one after the other: either rawlog layout, as the test decides.
class RawObjectWriter {
 public:
  explicit RawObjectWriter(const std::string& path) : out_(path), arch_(out_) {}
  template <class T>
  void write(const T& object) {
    arch_.WriteObject(&object);
  }

 private:
  mrpt::io::CFileOutputStream out_;
  mrpt::serialization::CArchiveStreamBase<mrpt::io::CFileOutputStream> arch_;
};

}  // namespace dlo::test
