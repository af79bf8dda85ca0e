// Packs simulated sweeps into MRPT Velodyne observations made of genuine data packets.
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <Eigen/Geometry>
#include <string>

#include "dlo/sim/sweep_simulator.h"

namespace dlo {

/**
 * One sweep as an mrpt::obs::CObservationVelodyneScan: the returns are stored in Velodyne
 * data packets (12 blocks, 2 mm range units, 0.01 deg azimuth units, strongest return), with
 * the sensor's elevation table in `calibration`, so that MRPT's own generatePointCloud()
 * decodes them into points in the SENSOR frame, and `sensorPose` carries the mounting pose on
 * the vehicle.
 *
 * Times: `timestamp` is the sweep's reference time (its first firing) = `epoch` + the time
 * since the sequence start. Each packet's GPS field holds the microseconds since the top of
 * the hour of its first firing, so generatePointCloud(generatePerPointTimestamp = true)
 * returns, per point, the time of its packet's first firing; the exact firing time of a point
 * adds the Velodyne block/laser offsets (see datasets/README.md).
 */
mrpt::obs::CObservationVelodyneScan::Ptr toVelodyneScan(const sim::Sweep& sweep,
                                                        const sim::SweepSimulator& simulator,
                                                        const Eigen::Isometry3d& sensorMount,
                                                        mrpt::Clock::time_point epoch,
                                                        const std::string& sensorLabel);

/// `epoch` plus a duration in nanoseconds, at MRPT's 100 ns clock resolution.
mrpt::Clock::time_point addNanoseconds(mrpt::Clock::time_point epoch, int64_t ns);

}  // namespace dlo
