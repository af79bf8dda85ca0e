#include "dlo/formats/kitti_sequence.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dlo/files/error.h"

namespace dlo {

namespace fs = std::filesystem;

namespace {

/// Calls `parse(line, line_number)` for every non-blank line of `path`.
template <class F>
void forEachLine(const std::string& path, F parse) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open '" + path + "': no such file or not readable.");
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    parse(line, number);
  }
}

/// Exactly `count` finite numbers from `text`, or an InputError naming file and line.
std::vector<double> parseNumbers(const std::string& text, size_t count, const std::string& path,
                                 size_t line, const std::string& what) {
  std::istringstream in(text);
  std::vector<double> v(count);
  std::string rest;
  for (double& x : v) {
    if (!(in >> x) || !std::isfinite(x)) {
      throw InputError("'" + path + "' line " + std::to_string(line) + ": expected " + what +
                       ", got '" + text + "'.");
    }
  }
  if (in >> rest) {
    throw InputError("'" + path + "' line " + std::to_string(line) + ": expected " + what +
                     ", got extra text '" + rest + "'.");
  }
  return v;
}

Eigen::Isometry3d isometryFromRowMajor3x4(const std::vector<double>& v) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = v[4 * r + c];
  }
  return Eigen::Isometry3d(m);
}

bool isScanFile(const fs::path& p) {
  const std::string name = p.filename().string();
  auto ends = [&](const std::string& s) {
    return name.size() >= s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
  };
  return ends(".bin") || ends(".bin.gz");
}

void requireOnePerScan(size_t lines, size_t scans, const std::string& path) {
  if (lines != scans) {
    throw InputError("'" + path + "' has " + std::to_string(lines) + " lines but velodyne/ holds " +
                     std::to_string(scans) + " scans; expected one line per scan.");
  }
}

}  // namespace

std::vector<double> readKittiTimes(const std::string& path) {
  std::vector<double> times;
  forEachLine(path, [&](const std::string& line, size_t number) {
    times.push_back(parseNumbers(line, 1, path, number, "one time in seconds")[0]);
  });
  return times;
}

std::vector<Eigen::Isometry3d> readKittiPoses(const std::string& path) {
  std::vector<Eigen::Isometry3d> poses;
  forEachLine(path, [&](const std::string& line, size_t number) {
    poses.push_back(isometryFromRowMajor3x4(
        parseNumbers(line, 12, path, number, "12 numbers (a row-major 3x4 pose matrix)")));
  });
  return poses;
}

Eigen::Isometry3d readKittiCalibTr(const std::string& path) {
  bool found = false;
  Eigen::Isometry3d tr = Eigen::Isometry3d::Identity();
  forEachLine(path, [&](const std::string& line, size_t number) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) {
      throw InputError("'" + path + "' line " + std::to_string(number) +
                       ": expected 'NAME: numbers', got '" + line + "'.");
    }
    const std::string key = line.substr(0, colon);
    if (key != "Tr" && key != "Tr_velo_to_cam") return;  // P0..P3 are camera projections
    tr = isometryFromRowMajor3x4(parseNumbers(line.substr(colon + 1), 12, path, number,
                                              "12 numbers after 'Tr:' (row-major 3x4)"));
    found = true;
  });
  if (!found) throw InputError("'" + path + "' has no 'Tr:' line (LiDAR to camera transform).");
  return tr;
}

std::vector<Eigen::Isometry3d> cameraPosesToLidar(const std::vector<Eigen::Isometry3d>& cam_poses,
                                                  const Eigen::Isometry3d& tr_velo_to_cam) {
  const Eigen::Isometry3d tr_inv = tr_velo_to_cam.inverse();
  std::vector<Eigen::Isometry3d> out;
  out.reserve(cam_poses.size());
  for (const auto& p : cam_poses) out.push_back(tr_inv * p * tr_velo_to_cam);
  return out;
}

KittiSequence readKittiSequence(const std::string& dir) {
  if (!fs::is_directory(dir)) {
    throw InputError("KITTI sequence folder '" + dir + "' does not exist or is not a folder.");
  }
  // KITTI's layout keeps the scans in velodyne/; a plain folder of scans is accepted too.
  const fs::path velodyne = fs::path(dir) / "velodyne";
  const fs::path scans = fs::is_directory(velodyne) ? velodyne : fs::path(dir);
  KittiSequence seq;
  for (const auto& entry : fs::directory_iterator(scans)) {
    if (entry.is_regular_file() && isScanFile(entry.path())) {
      seq.scan_files.push_back(entry.path().string());
    }
  }
  std::sort(seq.scan_files.begin(), seq.scan_files.end());
  if (seq.scan_files.empty()) {
    throw InputError("KITTI sequence folder '" + dir +
                     "' holds no .bin or .bin.gz scan (expected velodyne/000000.bin, ... or "
                     "000000.bin, ... in the folder itself).");
  }
  const size_t n = seq.scan_files.size();

  const fs::path times = fs::path(dir) / "times.txt";
  if (fs::exists(times)) {
    seq.times = readKittiTimes(times.string());
    requireOnePerScan(seq.times.size(), n, times.string());
    seq.times_from_file = true;
  } else {
    for (size_t i = 0; i < n; ++i) seq.times.push_back(0.1 * static_cast<double>(i));  // 10 Hz
  }

  const fs::path poses = fs::path(dir) / "poses.txt";
  if (fs::exists(poses)) {
    seq.lidar_poses = readKittiPoses(poses.string());
    requireOnePerScan(seq.lidar_poses.size(), n, poses.string());
    const fs::path calib = fs::path(dir) / "calib.txt";
    if (fs::exists(calib)) {
      seq.lidar_poses = cameraPosesToLidar(seq.lidar_poses, readKittiCalibTr(calib.string()));
      seq.poses_from_camera_frame = true;
    }
  }
  return seq;
}

}  // namespace dlo
