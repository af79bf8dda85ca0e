/// \file kitti_folder_writer.h
/// \brief Writing scans as a KITTI odometry sequence folder, the layout readKittiSequence() reads:
/// for programs that take KITTI folders (other odometries, their evaluation scripts).
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "dlo/core/point_cloud.h"
#include "dlo/files/atomic_file.h"

namespace dlo {

/// Streams scans into a KITTI sequence folder `dir`: `velodyne/000000.bin`, ... (float32 x, y, z,
/// intensity per point; DLO's scans carry no intensity, written as 0), `times.txt` (one time in
/// seconds per scan, 9 decimals, the scans' own stamps) and, when poses are given, `poses.txt`
/// (one row-major 3x4 matrix per scan, as readKittiPoses() reads them; no calib.txt, so they are
/// the poses of the frame the points are in). The folder is built as `dir + ".tmp"` and commit()
/// renames it, so `dir` is either complete or absent; a writer destroyed without commit() (an
/// error part way) keeps what it wrote as `dir + ".partial"`.
class KittiFolderWriter {
 public:
  /// \throws InputError naming the folder if `dir` exists and is not an empty folder;
  ///         OutputError if the temporary folder cannot be created.
  explicit KittiFolderWriter(const std::string& dir);
  KittiFolderWriter(const KittiFolderWriter&) = delete;
  KittiFolderWriter& operator=(const KittiFolderWriter&) = delete;

  /// Appends one scan taken at `time` (seconds). \throws OutputError naming the file if it
  /// cannot be written.
  void write(double time, const PointCloud& points);

  /// Scans written so far.
  size_t count() const { return times_.size(); }

  /// Writes times.txt and, if `poses` is not empty, poses.txt, then renames the folder to its
  /// final name. \throws InputError if `poses` is neither empty nor one per scan; OutputError if
  /// a file cannot be written or renamed.
  void commit(const std::vector<Eigen::Isometry3d>& poses = {});

  /// Where the scans written so far are kept if commit() is never called.
  std::string partialPath() const { return output_.partialPath(); }

 private:
  AtomicOutput output_;
  std::vector<double> times_;
};

}  // namespace dlo
