/// \file scan_source.h
/// \brief A stream of timestamped LiDAR scans (from a rawlog, a Velodyne pcap, ...), the form in
/// which the odometry consumes its input.
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation.h>

#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// One scan, ready for the odometry.
struct TimedScan {
  /// Time of the observation (MRPT's `CObservation::timestamp`: for a Velodyne scan, the first
  /// firing of its first packet).
  mrpt::Clock::time_point timestamp{};
  /// Label of the sensor that produced it (`CObservation::sensorLabel`).
  std::string sensor_label;
  /// MRPT class of the source observation, e.g. "CObservationVelodyneScan".
  std::string source_class;
  /// Points in the VEHICLE frame (the observation's sensorPose applied), metres, all finite and
  /// within the range limits.
  PointCloud points;
  /// Time of each point in seconds relative to `timestamp` (same order as `points`); empty when
  /// the observation carries no per-point times.
  std::vector<float> point_times;
  /// Pose of the sensor in the vehicle frame (the observation's sensorPose; identity where the
  /// input has none): where the points' rings are centred (dlo::estimateRings).
  Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();
  /// Beams (rings) of the sensor where the observation says: the calibration table or laser ids
  /// of a CObservationVelodyneScan, the rows of a CObservationRotatingScan; 0 = unknown (point
  /// clouds, 3D range scans, KITTI files).
  int beams = 0;
  /// Points dropped because a coordinate was NaN or infinite.
  size_t dropped_non_finite = 0;
  /// Points dropped by ScanSourceOptions::min_range / max_range.
  size_t dropped_by_range = 0;
  /// Index of the entry it came from (rawlog: serialized object, counting actions and sensory
  /// frames; pcap: scan number), for messages that point into the file.
  size_t entry_index = 0;

  /// The observation the scan was made from, as the input stores it (null where the input is
  /// not MRPT observations: KITTI files): what an annotated rawlog writes back.
  mrpt::obs::CObservation::Ptr observation;
  /// `timestamp` as seconds since the Unix epoch (MRPT's double time convention).
  double timestampSeconds() const { return mrpt::Clock::toDouble(timestamp); }
};

/// What to keep from the input. Ranges are measured from the SENSOR origin, before sensorPose is
/// applied, since that is what the sensor's own limits refer to.
struct ScanSourceOptions {
  /// Points closer than this (metres) are dropped, e.g. returns from the vehicle itself.
  double min_range = 0.0;
  /// Points farther than this (metres) are dropped.
  double max_range = std::numeric_limits<double>::infinity();
  /// If not empty, only observations with this sensorLabel are turned into scans; the others
  /// (whatever their class) are counted in ScanSourceStats::skipped_by_label.
  std::string sensor_label;
};

/// Counters of a ScanSource, for the summary a program prints at the end.
struct ScanSourceStats {
  /// Serialized entries (rawlog objects, pcap scans) read successfully.
  size_t entries_read = 0;
  /// Scans handed out by next().
  size_t scans = 0;
  /// Observations whose label did not match ScanSourceOptions::sensor_label.
  size_t skipped_by_label = 0;
  /// Observations (and other objects) not turned into scans, by MRPT class name.
  std::map<std::string, size_t> skipped_by_class;
  /// Why each class in skipped_by_class was skipped, when it is a known class that cannot be
  /// converted (not just an unrelated sensor such as odometry or GPS).
  std::map<std::string, std::string> skip_reasons;
  /// Supported observations that held no point once filtered (not handed out).
  size_t empty_scans = 0;
  /// Points dropped for non-finite coordinates, over all scans.
  size_t dropped_non_finite = 0;
  /// Points dropped by the range limits, over all scans.
  size_t dropped_by_range = 0;
  /// Empty if the input ended cleanly; otherwise one sentence saying where it broke (entry index
  /// and byte offset). The scans before that point have been handed out.
  std::string error;
};

/// Several lines describing `stats` for a person: scans, skipped classes with reasons, dropped
/// points, and the error if any. Each line ends with '\n'.
std::string describeScanSourceStats(const ScanSourceStats& stats);

/// A source of TimedScans read one at a time, so that inputs of any length fit in memory.
class ScanSource {
 public:
  virtual ~ScanSource() = default;

  /// Reads up to the next scan. \return false at the end of the input, or where the input broke:
  /// then stats().error says where; the scans already returned stay valid.
  virtual bool next(TimedScan& scan) = 0;

  /// Counters so far.
  virtual const ScanSourceStats& stats() const = 0;
};

}  // namespace dlo
