// Packs simulated sweeps into MRPT Velodyne observations made of genuine data packets.
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/poses/CPose3D.h>
#include <Eigen/Geometry>
#include <string>

#include "dlo/sim/sweep_simulator.h"

namespace dlo {

/// Metres per range unit of the simulated observations: a Velodyne data packet's 2 mm, also
/// used by the rotating-scan form (sweep_observations.h).
inline constexpr double kRangeUnit = 0.002;

/**
 * One sweep as an mrpt::obs::CObservationVelodyneScan, in two forms:
 *
 * - `point_cloud`: the measured points in the SENSOR frame, firing-major and laser-minor,
 *   with `intensity`, `laser_id` (ring) and `timestamp`: the absolute time at which that laser
 *   fired (100 ns resolution). This is what MRPT-based readers use when it is present (the DLO
 *   adapter, MOLA), and it carries the exact per-point times needed for deskewing.
 * - `scan_packets`: the same returns as genuine Velodyne data packets (12 blocks of 32
 *   returns, 2 mm range units, 0.01 deg azimuth units, strongest return, GPS field = us since
 *   the top of the hour of the packet's first firing) plus the elevation table in
 *   `calibration`, as a real capture stores them. Caveat: MRPT 2.5's generatePointCloud()
 *   decodes only the first 16 returns of every block, so calling it replaces the complete
 *   `point_cloud` with part of it; do not re-decode.
 *
 * `timestamp` is the sweep's reference time (its first firing) = `epoch` + the time since
 * the sequence start; `sensorPose` is the mounting pose on the vehicle.
 */
mrpt::obs::CObservationVelodyneScan::Ptr toVelodyneScan(const sim::Sweep& sweep,
                                                        const sim::SweepSimulator& simulator,
                                                        const Eigen::Isometry3d& sensorMount,
                                                        mrpt::Clock::time_point epoch,
                                                        const std::string& sensorLabel);

/// `epoch` plus a duration in nanoseconds, at MRPT's 100 ns clock resolution.
mrpt::Clock::time_point addNanoseconds(mrpt::Clock::time_point epoch, int64_t ns);

/// The sensor's mounting pose on the vehicle as an observation's sensorPose.
mrpt::poses::CPose3D mountPose(const Eigen::Isometry3d& sensorMount);

}  // namespace dlo
