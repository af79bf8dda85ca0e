#include "sweep_observations.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <algorithm>
#include <cmath>

#include "velodyne_observation.h"

namespace dlo {

mrpt::obs::CObservationRotatingScan::Ptr toRotatingScan(const sim::Sweep& sweep,
                                                        const sim::SweepSimulator& simulator,
                                                        const Eigen::Isometry3d& sensorMount,
                                                        mrpt::Clock::time_point epoch,
                                                        const std::string& sensorLabel) {
  const sim::LidarModel& m = simulator.model();
  auto obs = mrpt::obs::CObservationRotatingScan::Create();
  obs->sensorLabel = sensorLabel;
  obs->timestamp = addNanoseconds(epoch, sweep.referenceTimeNs);
  obs->originalReceivedTimestamp = obs->timestamp;
  obs->has_satellite_timestamp = true;
  obs->sensorPose = mountPose(sensorMount);
  obs->minRange = m.minRange;
  obs->maxRange = m.maxRange;
  obs->lidarModel = "OS1-" + std::to_string(m.laserCount());
  obs->rowCount = static_cast<uint16_t>(sweep.lasers);
  obs->columnCount = static_cast<uint16_t>(sweep.firings);
  obs->rangeResolution = kRangeUnit;
  // The simulator's azimuths run clockwise; MRPT's counter-clockwise.
  const double first = -simulator.azimuthDeg(simulator.pointTimeNs(sweep, 0, 0));
  obs->startAzimuth = std::remainder(first, 360.0) * M_PI / 180.0;
  const double steps = static_cast<double>(std::max(sweep.firings - 1, 0));
  obs->azimuthSpan = m.spinDirection * 2.0 * M_PI * steps * static_cast<double>(m.firingPeriodNs) /
                     static_cast<double>(simulator.revolutionNs());
  obs->sweepDuration = steps * static_cast<double>(m.firingPeriodNs) * 1e-9;
  obs->rangeImage.setZero(sweep.lasers, sweep.firings);
  obs->intensityImage.setZero(sweep.lasers, sweep.firings);
  for (int f = 0; f < sweep.firings; ++f) {
    for (int l = 0; l < sweep.lasers; ++l) {
      const size_t idx = sweep.index(f, l);
      if (sweep.range[idx] <= 0.0f) continue;
      obs->rangeImage(l, f) =
          static_cast<uint16_t>(std::min<long>(std::lround(sweep.range[idx] / kRangeUnit), 65535));
      obs->intensityImage(l, f) = sweep.intensity[idx];
    }
  }
  return obs;
}

mrpt::obs::CObservationPointCloud::Ptr withoutPointTimes(const sim::Sweep& sweep,
                                                         const sim::SweepSimulator& simulator,
                                                         const Eigen::Isometry3d& sensorMount,
                                                         mrpt::Clock::time_point epoch,
                                                         const std::string& sensorLabel) {
  auto obs = mrpt::obs::CObservationPointCloud::Create();
  obs->sensorLabel = sensorLabel;
  obs->timestamp = addNanoseconds(epoch, sweep.referenceTimeNs);
  obs->sensorPose = mountPose(sensorMount);
  auto map = mrpt::maps::CSimplePointsMap::Create();
  map->reserve(static_cast<size_t>(
      std::count_if(sweep.range.begin(), sweep.range.end(), [](float r) { return r > 0.0f; })));
  for (int f = 0; f < sweep.firings; ++f) {
    for (int l = 0; l < sweep.lasers; ++l) {
      if (sweep.range[sweep.index(f, l)] <= 0.0f) continue;
      const Eigen::Vector3d p = simulator.sensorPoint(sweep, f, l);
      map->insertPointFast(static_cast<float>(p.x()), static_cast<float>(p.y()),
                           static_cast<float>(p.z()));
    }
  }
  obs->pointcloud = map;
  return obs;
}

}  // namespace dlo
