/// \file trajectory_io.h
/// \brief Reading and writing trajectories in the TUM and KITTI text formats.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "dlo/files/atomic_file.h"

#include "dlo/metrics/trajectory.h"

namespace dlo::metrics {

/// Text formats of trajectory files.
enum class TrajectoryFormat {
  kTum,    ///< "t x y z qx qy qz qw" per line (TUM RGB-D, evo); '#' starts a comment
  kKitti,  ///< 12 numbers per line: the row-major 3x4 matrix [R | t]; no timestamps
};

/// Guesses the format from the first non-comment, non-empty line: 8 numbers are TUM, 12 KITTI.
/// \throws std::runtime_error naming the file (and line) if it cannot be read or has neither.
TrajectoryFormat detectTrajectoryFormat(const std::string& path);

/// Reads a TUM file. Quaternions are normalised (files often carry 6 decimals).
/// \throws std::runtime_error naming the file and the line number of a malformed line.
Trajectory readTumTrajectory(const std::string& path);

/// Reads a KITTI pose file. `times` gives the stamp of each pose (e.g. read with
/// readTimestamps() from KITTI's times.txt); when empty, pose i is stamped i seconds. The rotation
/// part is re-orthonormalised.
/// \throws std::runtime_error naming the file and line if a line is malformed, or if `times` is
///         non-empty and its size differs from the number of poses.
Trajectory readKittiTrajectory(const std::string& path, const std::vector<double>& times = {});

/// Reads either format, as detected by detectTrajectoryFormat(); `kitti_times` is used only for
/// KITTI files (see readKittiTrajectory()).
Trajectory readTrajectory(const std::string& path, const std::vector<double>& kitti_times = {});

/// Reads one number per line (KITTI's times.txt); '#' comments and empty lines are skipped.
/// \throws std::runtime_error naming the file and line of a malformed line.
std::vector<double> readTimestamps(const std::string& path);

/// What a TUM file written by writeTumTrajectory() starts with.
enum class TumHeader {
  kColumnNames,  ///< a comment line "# t x y z qx qy qz qw"
  kNone,         ///< nothing: the first pose is the first line
};

/// A TUM file written pose by pose, the one TUM writer of DLO (9 decimals: nanosecond stamps,
/// sub-millimetre positions): a long run streams its poses. Atomic: the file is written under a
/// temporary name (dlo::AtomicOutput) and renamed by commit(); destroyed without commit(),
/// nothing is left and `path` keeps what it held.
class TumWriter {
 public:
  /// \param header comment lines written first, each "# ...\n"; empty for none.
  /// \throws dlo::OutputError naming `path` if it cannot be created.
  TumWriter(const std::string& path, const std::string& header);
  ~TumWriter();
  TumWriter(const TumWriter&) = delete;
  TumWriter& operator=(const TumWriter&) = delete;

  /// One pose, stamped `time` seconds.
  void write(double time, const Eigen::Isometry3d& pose);
  /// One pose, stamped exactly `seconds` + `nanoseconds` (no rounding through a double: a
  /// simulator's clock).
  void write(std::int64_t seconds, std::int64_t nanoseconds, const Eigen::Isometry3d& pose);
  /// Closes the file and gives it its name.
  /// \throws dlo::OutputError naming `path` if writing failed (a full disk).
  void commit();

 private:
  void writePose(const Eigen::Isometry3d& pose);

  AtomicOutput output_;
  std::FILE* file_ = nullptr;
};

/// Writes a whole trajectory as a TUM file through TumWriter, so `path` is either complete or
/// untouched.
/// \throws dlo::OutputError (a std::runtime_error) naming the file if it cannot be written.
void writeTumTrajectory(const std::string& path, const Trajectory& trajectory,
                        TumHeader header = TumHeader::kColumnNames);

/// Writes a KITTI pose file (12 numbers per line, timestamps are not stored), atomically like
/// writeTumTrajectory().
void writeKittiTrajectory(const std::string& path, const Trajectory& trajectory);

/// Writes one timestamp per line (KITTI's times.txt), atomically.
void writeTimestamps(const std::string& path, const std::vector<double>& times);

}  // namespace dlo::metrics
