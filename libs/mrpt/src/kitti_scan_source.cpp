#include "dlo/mrpt/kitti_scan_source.h"

#include <cmath>
#include <exception>

#include "dlo/formats/kitti_bin.h"

namespace dlo {

KittiScanSource::KittiScanSource(const std::string& dir, const ScanSourceOptions& options)
    : sequence_(readKittiSequence(dir)), options_(options) {}

bool KittiScanSource::next(TimedScan& scan) {
  if (index_ >= sequence_.scan_files.size() || !stats_.error.empty()) return false;
  const std::string& file = sequence_.scan_files[index_];
  std::vector<float> records;
  try {
    records = readKittiBinRecords(file);
  } catch (const std::exception& e) {
    stats_.error = e.what();
    return false;
  }
  scan = TimedScan();
  scan.timestamp = mrpt::Clock::fromDouble(sequence_.times[index_]);
  scan.sensor_label = "VELODYNE";
  scan.source_class = "KITTI .bin";
  scan.entry_index = index_;
  scan.points.reserve(records.size() / 4);
  const double min_sq = options_.min_range * options_.min_range;
  const double max_sq = options_.max_range * options_.max_range;
  for (size_t i = 0; i + 3 < records.size(); i += 4) {
    const Eigen::Vector3f p(records[i], records[i + 1], records[i + 2]);
    if (!p.allFinite()) {
      ++scan.dropped_non_finite;
      continue;
    }
    const double r2 = static_cast<double>(p.squaredNorm());
    if (r2 < min_sq || r2 > max_sq) {
      ++scan.dropped_by_range;
      continue;
    }
    scan.points.push_back(p);
  }
  ++index_;
  ++stats_.entries_read;
  ++stats_.scans;
  return true;
}

}  // namespace dlo
