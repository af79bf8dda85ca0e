// Simulated sweeps as MRPT observations other than Velodyne scans: range images of the sensors
// that do not fit Velodyne packets, and point clouds without per-point times.
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <Eigen/Geometry>
#include <string>

#include "dlo/sim/sweep_simulator.h"

namespace dlo {

/**
 * One sweep of an Ouster-like sensor (OS64, OS128) as an mrpt::obs::CObservationRotatingScan,
 * the form MRPT 2.5 gives ring-organised LiDAR data:
 *
 * - `rangeImage` (`rowCount` beams x `columnCount` firings, 2 mm units, 0 = no return) and
 *   `intensityImage`; row r is beam r of the model's elevation table (row 0 the highest);
 * - `startAzimuth`: azimuth of the first column, radians counter-clockwise from the sensor's
 *   +x; `azimuthSpan`: from the first column to the last, > 0 counter-clockwise, < 0
 *   clockwise (MRPT's convention); column c lies at startAzimuth + c * azimuthSpan /
 *   (columnCount - 1) and was fired c * sweepDuration / (columnCount - 1) seconds after
 *   `timestamp` (every beam of a column fires at once);
 * - `lidarModel` "OS1-<beams>": MRPT 2.5 stores no elevation table, so readers take the
 *   nominal Ouster OS1 layout (beams spread evenly over +22.5..-22.5 deg) from this name.
 *
 * `timestamp` is the sweep's reference time (its first column) = `epoch` + the time since the
 * sequence start; `sensorPose` is the mounting pose on the vehicle.
 */
mrpt::obs::CObservationRotatingScan::Ptr toRotatingScan(const sim::Sweep& sweep,
                                                        const sim::SweepSimulator& simulator,
                                                        const Eigen::Isometry3d& sensorMount,
                                                        mrpt::Clock::time_point epoch,
                                                        const std::string& sensorLabel);

/// The measured points of a sweep (sensor frame, firing order: by firing, then by laser) as a
/// CObservationPointCloud of a CSimplePointsMap without per-point times, what KITTI files and
/// most point-cloud inputs give; timestamp, label and sensorPose as toRotatingScan().
mrpt::obs::CObservationPointCloud::Ptr withoutPointTimes(const sim::Sweep& sweep,
                                                         const sim::SweepSimulator& simulator,
                                                         const Eigen::Isometry3d& sensorMount,
                                                         mrpt::Clock::time_point epoch,
                                                         const std::string& sensorLabel);

}  // namespace dlo
