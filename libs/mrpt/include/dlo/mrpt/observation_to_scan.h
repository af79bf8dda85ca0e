/// \file observation_to_scan.h
/// \brief Turning one MRPT observation into a TimedScan: vehicle-frame points, per-point times,
/// range and finiteness filtering.
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <string>
#include <vector>

#include "dlo/mrpt/scan_source.h"

namespace dlo {

/// Outcome of observationToTimedScan().
enum class ObservationConversion {
  kConverted,      ///< `scan` holds the observation's points (possibly none after filtering).
  kUnsupported,    ///< Not a point-cloud-like class: the caller counts it as skipped.
  kUnrecoverable,  ///< A point-cloud-like class whose points cannot be recovered; see `reason`.
};

/// Converts `obs` into `scan` (all fields but entry_index). Supported:
/// - CObservationVelodyneScan: its stored point cloud, or generatePointCloud() with per-point
///   timestamps; `beams` from its calibration table (or its laser ids);
/// - CObservationRotatingScan whose lidarModel names a layout DLO knows ("OS1-<rows>": Ouster
///   OS1, rows evenly over +22.5..-22.5 deg, as dlo-simulate writes its OS64 / OS128 sensors):
///   its range image column by column, each column at its azimuth and time interpolated from
///   startAzimuth, azimuthSpan and sweepDuration; `beams` = rowCount. Any other lidarModel is
///   kUnrecoverable: MRPT 2.5 stores no elevation angle per ring, so points cannot be rebuilt;
/// - CObservationPointCloud: its point map (per-point times: see pointCloudObservationTimes());
/// - CObservation3DRangeScan: its 3D points, or its range image unprojected with the camera
///   intrinsics when it has no 3D points.
/// An observation MRPT throws on while decoding it (corrupt camera parameters or
/// calibration, a missing externally stored file): the exception does not escape.
/// Non-const because lazily-loaded observations must be loaded and range images unprojected.
/// \param reason set to one sentence when the result is kUnrecoverable.
ObservationConversion observationToTimedScan(mrpt::obs::CObservation& obs,
                                             const ScanSourceOptions& options, TimedScan& scan,
                                             std::string& reason);

/// HOOK for per-point times stored in a CObservationPointCloud. MRPT 2.5 point maps have no time
/// channel (CPointsMapXYZIRT came later), so a writer that wants to carry times there must agree
/// on a convention with this function. None exists: the simulator (datasets/README.md) writes
/// CObservationVelodyneScan with absolute `point_cloud.timestamp` instead, which
/// observationToTimedScan() reads directly without re-decoding. So this returns an empty vector;
/// if a convention is ever agreed, decode it here and every reader picks it up.
/// \return one time per point of `obs.pointcloud` in seconds relative to obs.timestamp, or empty.
std::vector<float> pointCloudObservationTimes(const mrpt::obs::CObservationPointCloud& obs);

/// Short class name of a serializable ("CObservationOdometry", without the namespace).
std::string shortClassName(const mrpt::serialization::CSerializable& object);

/// What every ScanSource does with one observation: the sensor-label filter (before conversion:
/// other sensors' observations may be costly to convert), observationToTimedScan(), and the
/// counters of `stats` (skipped labels and classes with their reasons, dropped points, empty
/// scans, scans).
/// \return true when `scan` holds a non-empty scan to hand out.
bool admitObservation(mrpt::obs::CObservation& obs, const ScanSourceOptions& options,
                      TimedScan& scan, ScanSourceStats& stats);

}  // namespace dlo
