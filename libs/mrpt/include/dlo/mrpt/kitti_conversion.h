/// \file kitti_conversion.h
/// \brief A KITTI odometry sequence folder to an MRPT rawlog and a TUM ground truth.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

namespace dlo {

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

}  // namespace dlo
