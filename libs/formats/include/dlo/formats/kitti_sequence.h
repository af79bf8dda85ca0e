/// \file kitti_sequence.h
/// \brief A KITTI odometry sequence folder: scan files, times and ground-truth poses in the
/// LiDAR frame.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace dlo {

/// What a KITTI odometry sequence folder holds, read and checked, scans not loaded.
struct KittiSequence {
  /// `velodyne/*.bin` and `velodyne/*.bin.gz` (or the folder's own), sorted by name (KITTI names
  /// them 000000.bin, ...).
  std::vector<std::string> scan_files;
  /// Time of each scan in seconds (from `times.txt`, or 0.1 s apart when it is missing).
  std::vector<double> times;
  /// True if `times` came from `times.txt`.
  bool times_from_file = false;
  /// Pose of the LiDAR of each scan in the LiDAR frame of the first one; empty without
  /// `poses.txt`.
  std::vector<Eigen::Isometry3d> lidar_poses;
  /// True if `poses.txt` was converted from the camera to the LiDAR frame with `calib.txt`'s Tr.
  bool poses_from_camera_frame = false;
};

/// Reads the folder `dir`: the scans in `velodyne/` (or, without that subfolder, in `dir`
/// itself; at least one), `times.txt`, `poses.txt` and `calib.txt` (optional). KITTI's poses.txt
/// gives the left camera's poses P_cam; with calib.txt they become LiDAR poses T_velo = Tr^-1 *
/// P_cam * Tr, where Tr maps LiDAR points into the camera frame. Without calib.txt, poses.txt is
/// taken to hold LiDAR poses already. \throws InputError naming the file (and line) when the folder
/// or velodyne/ is missing, a line
///         is malformed, or times/poses do not have one line per scan.
KittiSequence readKittiSequence(const std::string& dir);

/// One time per non-blank line of a KITTI times.txt. \throws InputError naming file and line.
std::vector<double> readKittiTimes(const std::string& path);

/// One pose per non-blank line of a KITTI poses.txt (12 numbers: a row-major 3x4 matrix).
/// \throws InputError naming file and line.
std::vector<Eigen::Isometry3d> readKittiPoses(const std::string& path);

/// The `Tr:` transform of a KITTI calib.txt (LiDAR to left camera, 12 numbers, row-major 3x4).
/// \throws InputError naming file and line for a malformed line, or if Tr is missing.
Eigen::Isometry3d readKittiCalibTr(const std::string& path);

/// Expresses camera-frame KITTI poses as LiDAR poses: T_velo = Tr^-1 * P_cam * Tr.
std::vector<Eigen::Isometry3d> cameraPosesToLidar(const std::vector<Eigen::Isometry3d>& cam_poses,
                                                  const Eigen::Isometry3d& tr_velo_to_cam);

}  // namespace dlo
