/// \file kitti_scan_source.h
/// \brief A KITTI odometry sequence folder read scan by scan, as dlo-slam's input.
#pragma once

#include <string>

#include "dlo/formats/kitti_sequence.h"
#include "dlo/mrpt/scan_source.h"

namespace dlo {

/// The scans of a KITTI odometry sequence folder (`velodyne/*.bin[.gz]`, `times.txt`,
/// optionally `poses.txt` and `calib.txt`; see readKittiSequence()), one file in memory at a
/// time. Points stay in the LiDAR frame (KITTI gives no mounting pose), without per-point
/// times; non-finite points are dropped and counted, the range limits apply from the sensor.
/// Scan times are `times.txt`'s seconds (or 0.1 s apart without it).
class KittiScanSource : public ScanSource {
 public:
  /// Reads and checks the folder (not the scans).
  /// \throws InputError naming the folder or file at fault, as readKittiSequence().
  explicit KittiScanSource(const std::string& dir, const ScanSourceOptions& options = {});

  /// The next scan. A file that cannot be read ends the input: stats().error names it and the
  /// scans already returned stay valid.
  bool next(TimedScan& scan) override;
  const ScanSourceStats& stats() const override { return stats_; }

  /// The folder as read: scan files, times and, with poses.txt, the LiDAR ground truth (in the
  /// LiDAR frame when calib.txt gives Tr).
  const KittiSequence& sequence() const { return sequence_; }

 private:
  KittiSequence sequence_;
  ScanSourceOptions options_;
  size_t index_ = 0;
  ScanSourceStats stats_;
};

}  // namespace dlo
