#include "dlo/mrpt/kitti_conversion.h"

#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <cmath>
#include <cstdio>

#include "dlo/files/error.h"
#include "dlo/formats/kitti_bin.h"
#include "dlo/formats/kitti_folder_writer.h"
#include "dlo/formats/kitti_sequence.h"
#include "dlo/metrics/timestamp_matching.h"
#include "dlo/metrics/trajectory_io.h"
#include "dlo/mrpt/rawlog_scan_source.h"
#include "dlo/mrpt/rawlog_writer.h"

namespace dlo {

namespace {

/// The pose of `ground_truth` (read from `gt_path`) stamped nearest each of `times`, within
/// `max_dt`, in the frame of the first. \throws InputError naming the first scan without one.
std::vector<Eigen::Isometry3d> posesAtTimes(const metrics::Trajectory& ground_truth,
                                            const std::vector<double>& times, double max_dt,
                                            const std::string& gt_path) {
  metrics::Trajectory scans;
  for (const double t : times) scans.push_back(t, Eigen::Isometry3d::Identity());
  std::vector<Eigen::Isometry3d> poses(times.size());
  std::vector<bool> found(times.size(), false);
  for (const auto& [scan, reference] : metrics::matchTimestamps(scans, ground_truth, max_dt)) {
    poses[scan] = ground_truth.poses[reference];
    found[scan] = true;
  }
  for (size_t i = 0; i < times.size(); ++i) {
    if (!found[i]) {
      char text[160];
      std::snprintf(text, sizeof text, "' has no pose within %.0f ms of scan %zu (t = %.6f s).",
                    1000.0 * max_dt, i, times[i]);
      throw InputError("ground truth '" + gt_path + text);
    }
  }
  const Eigen::Isometry3d first_inverse = poses.front().inverse();
  for (Eigen::Isometry3d& pose : poses) pose = first_inverse * pose;
  return poses;
}

}  // namespace

size_t loadKittiBinXYZI(const std::string& path, mrpt::maps::CPointsMapXYZI& map) {
  const std::vector<float> r = readKittiBinRecords(path);
  const size_t n = r.size() / 4;
  map.clear();
  map.reserve(n);
  size_t dropped = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* v = &r[4 * i];
    if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]))) {
      ++dropped;
      continue;
    }
    map.insertPointFast(v[0], v[1], v[2]);
    map.setPointIntensity(map.size() - 1, std::isfinite(v[3]) ? v[3] : 0.0f);
  }
  map.mark_as_modified();
  return dropped;
}

KittiConversionResult convertKittiSequence(const std::string& seq_dir,
                                           const std::string& out_rawlog, const std::string& gt_tum,
                                           const std::function<void(size_t, size_t)>& progress) {
  const KittiSequence seq = readKittiSequence(seq_dir);
  if (!gt_tum.empty() && seq.lidar_poses.empty()) {
    throw InputError("--gt needs ground-truth poses, but KITTI sequence folder '" + seq_dir +
                     "' has no poses.txt.");
  }
  KittiConversionResult result;
  result.times_from_file = seq.times_from_file;
  result.poses_from_camera_frame = seq.poses_from_camera_frame;

  RawlogWriter writer(out_rawlog);
  const size_t n = seq.scan_files.size();
  for (size_t i = 0; i < n; ++i) {
    auto obs = mrpt::obs::CObservationPointCloud::Create();
    auto map = mrpt::maps::CPointsMapXYZI::Create();
    try {
      result.dropped_non_finite += loadKittiBinXYZI(seq.scan_files[i], *map);
    } catch (const InputError& e) {
      throw InputError(std::string(e.what()) + " The " + std::to_string(writer.count()) +
                       " scans converted before it are kept in '" + writer.partialPath() + "'.");
    }
    obs->pointcloud = map;
    obs->sensorLabel = "VELODYNE";
    obs->sensorPose = mrpt::poses::CPose3D();
    obs->timestamp = mrpt::Clock::fromDouble(seq.times[i]);
    writer.write(*obs);
    ++result.scans;
    result.points += map->size();
    if (map->size() == 0) ++result.empty_scans;
    if (progress) progress(i + 1, n);
  }
  writer.commit();
  if (!gt_tum.empty()) {
    metrics::Trajectory ground_truth;
    ground_truth.times = seq.times;
    ground_truth.poses = seq.lidar_poses;
    metrics::writeTumTrajectory(gt_tum, ground_truth, metrics::TumHeader::kNone);
    result.poses = seq.lidar_poses.size();
  }
  return result;
}

RawlogToKittiResult convertRawlogToKitti(const std::string& rawlog, const std::string& out_dir,
                                         const std::string& gt_tum,
                                         const ScanSourceOptions& options, long max_scans,
                                         const std::function<void(size_t)>& progress) {
  metrics::Trajectory ground_truth;
  if (!gt_tum.empty()) {
    try {
      ground_truth = metrics::readTumTrajectory(gt_tum);
    } catch (const std::exception& e) {
      throw InputError("cannot read ground truth '" + gt_tum + "': " + e.what());
    }
  }
  RawlogScanSource source(rawlog, options);
  KittiFolderWriter writer(out_dir);
  RawlogToKittiResult result;
  std::vector<double> times;
  TimedScan scan;
  while ((max_scans < 0 || static_cast<long>(result.scans) < max_scans) && source.next(scan)) {
    writer.write(scan.timestampSeconds(), scan.points);
    times.push_back(scan.timestampSeconds());
    ++result.scans;
    result.points += scan.points.size();
    if (progress) progress(result.scans);
  }
  result.stats = source.stats();
  result.input_warning = source.stats().error;
  if (result.scans == 0) {
    throw InputError("rawlog '" + rawlog + "' holds no scan" +
                     (result.input_warning.empty() ? "." : ": " + result.input_warning));
  }
  std::vector<Eigen::Isometry3d> poses;
  if (!gt_tum.empty()) poses = posesAtTimes(ground_truth, times, 0.005, gt_tum);
  writer.commit(poses);
  result.poses = poses.size();
  return result;
}

}  // namespace dlo
