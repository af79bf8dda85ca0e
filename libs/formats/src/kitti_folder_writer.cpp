#include "dlo/formats/kitti_folder_writer.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "dlo/files/error.h"
#include "dlo/metrics/trajectory_io.h"

namespace dlo {

namespace fs = std::filesystem;

namespace {

/// `dir`, checked to be new or an empty folder before the output is set up beside it.
const std::string& newOrEmptyFolder(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !(fs::is_directory(dir, ec) && fs::is_empty(dir, ec))) {
    throw InputError("output folder '" + dir +
                     "' already exists and is not empty; give a new or empty folder.");
  }
  return dir;
}

}  // namespace

KittiFolderWriter::KittiFolderWriter(const std::string& dir) : output_(newOrEmptyFolder(dir)) {
  std::error_code ec;
  fs::create_directories(fs::path(output_.temp()) / "velodyne", ec);
  if (ec) {
    throw OutputError("cannot create folder '" + output_.temp() + "': " + ec.message() + ".");
  }
}

void KittiFolderWriter::write(double time, const PointCloud& points) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.bin", count());
  const fs::path path = fs::path(output_.temp()) / "velodyne" / name;
  std::vector<float> records;
  records.reserve(4 * points.size());
  for (const Eigen::Vector3f& p : points) records.insert(records.end(), {p.x(), p.y(), p.z(), 0.f});
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(records.data()),
            static_cast<std::streamsize>(records.size() * sizeof(float)));
  if (!out) throw OutputError("cannot write '" + path.string() + "' (disk full?).");
  times_.push_back(time);
  output_.setKeepPartial(true);
}

void KittiFolderWriter::commit(const std::vector<Eigen::Isometry3d>& poses) {
  if (!poses.empty() && poses.size() != count()) {
    throw InputError("KITTI folder '" + output_.path() + "': " + std::to_string(poses.size()) +
                     " poses given for " + std::to_string(count()) + " scans.");
  }
  metrics::Trajectory trajectory;
  trajectory.times = times_;
  trajectory.poses = poses;
  // Written atomically too (dlo::writeAtomically), with OutputErrors naming the file.
  metrics::writeTimestamps((fs::path(output_.temp()) / "times.txt").string(), times_);
  if (!poses.empty()) {
    metrics::writeKittiTrajectory((fs::path(output_.temp()) / "poses.txt").string(), trajectory);
  }
  output_.commit();  // replaces the empty folder the constructor accepted, if any
}

}  // namespace dlo
