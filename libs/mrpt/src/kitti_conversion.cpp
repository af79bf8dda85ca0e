#include "dlo/mrpt/kitti_conversion.h"

#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/obs/CObservationPointCloud.h>

#include "dlo/mrpt/input_error.h"
#include "dlo/mrpt/kitti_bin.h"
#include "dlo/mrpt/kitti_sequence.h"
#include "dlo/mrpt/rawlog_writer.h"
#include "dlo/mrpt/tum_file.h"

namespace dlo {

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
    writeTumTrajectory(gt_tum, seq.times, seq.lidar_poses);
    result.poses = seq.lidar_poses.size();
  }
  return result;
}

}  // namespace dlo
