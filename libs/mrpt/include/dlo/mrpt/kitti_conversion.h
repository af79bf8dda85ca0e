/// \file kitti_conversion.h
/// \brief A KITTI odometry sequence folder to an MRPT rawlog and a TUM ground truth, and back.
#pragma once

#include <mrpt/maps/CPointsMapXYZI.h>

#include <cstddef>
#include <functional>
#include <string>

#include "dlo/mrpt/scan_source.h"

namespace dlo {

/// Loads a KITTI Velodyne file (readKittiBinRecords()) into `map` (replacing its contents) with
/// reflectance as intensity. Used instead of CPointsMapXYZI::loadFromKittiVelodyneFile, which
/// neither reports why a file is bad nor drops non-finite points. \return the number of
/// non-finite points dropped. \throws InputError as readKittiBinRecords().
size_t loadKittiBinXYZI(const std::string& path, mrpt::maps::CPointsMapXYZI& map);

/// What convertKittiSequence() did, for the summary line of the converter.
struct KittiConversionResult {
  size_t scans = 0;               ///< Observations written.
  size_t points = 0;              ///< Points written, over all scans.
  size_t dropped_non_finite = 0;  ///< NaN/Inf points dropped.
  size_t empty_scans = 0;         ///< Scans written with no point (kept so indices match times).
  size_t poses = 0;               ///< Lines written to the TUM file (0 without one).
  bool times_from_file = false;   ///< false: times.txt was missing, 10 Hz assumed.
  bool poses_from_camera_frame = false;  ///< poses.txt converted with calib.txt's Tr.
};

/// Converts the KITTI sequence folder `seq_dir` (see readKittiSequence()) into `out_rawlog`:
/// one CObservationPointCloud (CPointsMapXYZI with reflectance, sensorLabel "VELODYNE",
/// sensorPose identity since KITTI points are in the LiDAR frame) per scan, observation-only
/// layout, one scan in memory at a time. If `gt_tum` is not empty, the LiDAR ground truth is
/// written there (requires poses.txt). `progress(done, total)` is called after each scan.
/// \throws InputError naming the file at fault; the observations written before it are kept
///         in `out_rawlog + ".partial"`, and an existing `out_rawlog` is left untouched.
KittiConversionResult convertKittiSequence(
    const std::string& seq_dir, const std::string& out_rawlog, const std::string& gt_tum,
    const std::function<void(size_t, size_t)>& progress = nullptr);

/// What convertRawlogToKitti() did, for the summary line of the converter.
struct RawlogToKittiResult {
  size_t scans = 0;           ///< Scans written to velodyne/.
  size_t points = 0;          ///< Points written, over all scans.
  size_t poses = 0;           ///< Lines written to poses.txt (0 without ground truth).
  ScanSourceStats stats;      ///< The rawlog reader's counters (skipped classes, dropped points).
  std::string input_warning;  ///< Where the rawlog broke, if it did (the scans before it are kept).
};

/// Writes the scans of `rawlog`, as RawlogScanSource gives them with `options` (vehicle frame,
/// range-filtered), into the KITTI folder `out_dir` (see KittiFolderWriter: the folder must be
/// new or empty; times.txt holds the scans' stamps), the first `max_scans` of them (all if
/// negative). If `gt_tum` is not empty, poses.txt holds the pose of that TUM ground truth
/// stamped nearest each scan (within 5 ms, the tolerance dlo-bench matches with), expressed in
/// the first scan's frame as KITTI's poses are; dlo-kitti2rawlog and dlo-slam read the folder
/// back as the same scans and times. `progress(done)` is called after each scan.
/// \throws InputError naming the file at fault: the rawlog or ground truth cannot be read, the
///         rawlog holds no scan, a scan has no ground-truth pose within 5 ms, the folder cannot be
///         written. A rawlog that breaks part way is not an error: the scans before the break
///         are written and input_warning says where it broke.
RawlogToKittiResult convertRawlogToKitti(const std::string& rawlog, const std::string& out_dir,
                                         const std::string& gt_tum,
                                         const ScanSourceOptions& options = {}, long max_scans = -1,
                                         const std::function<void(size_t)>& progress = nullptr);

}  // namespace dlo
