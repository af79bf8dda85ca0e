#include "dlo/mrpt/kitti_folder_writer.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "dlo/metrics/trajectory_io.h"
#include "dlo/mrpt/input_error.h"

namespace dlo {

namespace fs = std::filesystem;

KittiFolderWriter::KittiFolderWriter(const std::string& dir) : dir_(dir), temp_dir_(dir + ".tmp") {
  std::error_code ec;
  if (fs::exists(dir_, ec) && !(fs::is_directory(dir_, ec) && fs::is_empty(dir_, ec))) {
    throw InputError("output folder '" + dir_ +
                     "' already exists and is not empty; give a new or empty folder.");
  }
  fs::remove_all(temp_dir_, ec);  // left by a run that was killed
  fs::create_directories(fs::path(temp_dir_) / "velodyne", ec);
  if (ec) {
    throw InputError("cannot create folder '" + temp_dir_ + "': " + ec.message() + ".");
  }
}

KittiFolderWriter::~KittiFolderWriter() {
  if (committed_) return;
  std::error_code ec;
  if (count() > 0) {
    fs::remove_all(partialPath(), ec);
    fs::rename(temp_dir_, partialPath(), ec);
  } else {
    fs::remove_all(temp_dir_, ec);
  }
}

void KittiFolderWriter::write(double time, const PointCloud& points) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu.bin", count());
  const fs::path path = fs::path(temp_dir_) / "velodyne" / name;
  std::vector<float> records;
  records.reserve(4 * points.size());
  for (const Eigen::Vector3f& p : points) records.insert(records.end(), {p.x(), p.y(), p.z(), 0.f});
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(records.data()),
            static_cast<std::streamsize>(records.size() * sizeof(float)));
  if (!out) throw InputError("cannot write '" + path.string() + "' (disk full?).");
  times_.push_back(time);
}

void KittiFolderWriter::commit(const std::vector<Eigen::Isometry3d>& poses) {
  if (!poses.empty() && poses.size() != count()) {
    throw InputError("KITTI folder '" + dir_ + "': " + std::to_string(poses.size()) +
                     " poses given for " + std::to_string(count()) + " scans.");
  }
  metrics::Trajectory trajectory;
  trajectory.times = times_;
  trajectory.poses = poses;
  try {
    metrics::writeTimestamps((fs::path(temp_dir_) / "times.txt").string(), times_);
    if (!poses.empty()) {
      metrics::writeKittiTrajectory((fs::path(temp_dir_) / "poses.txt").string(), trajectory);
    }
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
  std::error_code ec;
  fs::remove(dir_, ec);  // an empty folder, checked by the constructor
  fs::rename(temp_dir_, dir_, ec);
  if (ec) {
    throw InputError("cannot rename '" + temp_dir_ + "' to '" + dir_ + "': " + ec.message() + ".");
  }
  committed_ = true;
}

}  // namespace dlo
