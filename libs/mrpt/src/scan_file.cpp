#include "dlo/mrpt/scan_file.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include "dlo/mrpt/input_error.h"
#include "dlo/mrpt/kitti_bin.h"
#include "dlo/mrpt/ply_file.h"
#include "dlo/mrpt/rawlog_scan_source.h"

namespace dlo {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

void requireReadable(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError("cannot open scan file '" + path + "': no such file or not readable.");
}

/// The first scan of a rawlog, reading one entry at a time.
PointCloud loadFirstRawlogScan(const std::string& path) {
  RawlogScanSource source(path);
  TimedScan scan;
  if (source.next(scan)) return std::move(scan.points);
  const ScanSourceStats& stats = source.stats();
  if (!stats.error.empty()) throw InputError(stats.error);
  throw InputError("rawlog '" + path + "' holds no point-cloud observation with points (read " +
                   std::to_string(stats.entries_read) + " entries).");
}

}  // namespace

ScanFormat scanFormatFromPath(const std::string& path) {
  const std::string p = lower(path);
  if (endsWith(p, ".bin") || endsWith(p, ".bin.gz")) return ScanFormat::kKittiBin;
  if (endsWith(p, ".ply")) return ScanFormat::kPly;
  if (endsWith(p, ".rawlog") || endsWith(p, ".rawlog.gz")) return ScanFormat::kRawlog;
  return ScanFormat::kUnknown;
}

PointCloud loadKittiBin(const std::string& path, size_t* dropped_non_finite) {
  const std::vector<float> records = readKittiBinRecords(path);
  const size_t n = records.size() / 4;
  PointCloud out;
  out.reserve(n);
  size_t dropped = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* v = &records[4 * i];
    if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) {
      out.emplace_back(v[0], v[1], v[2]);
    } else {
      ++dropped;
    }
  }
  if (dropped_non_finite) *dropped_non_finite = dropped;
  return out;
}

PointCloud loadScanFile(const std::string& path) {
  const ScanFormat format = scanFormatFromPath(path);
  if (format == ScanFormat::kUnknown) {
    throw InputError("unknown scan format for '" + path +
                     "': expected .bin, .bin.gz (KITTI), .ply or .rawlog.");
  }
  requireReadable(path);
  PointCloud points;
  switch (format) {
    case ScanFormat::kKittiBin:
      points = loadKittiBin(path);
      break;
    case ScanFormat::kPly:
      points = loadPlyFile(path);
      break;
    default:
      points = loadFirstRawlogScan(path);
      break;
  }
  if (points.empty()) throw InputError("scan file '" + path + "' holds no finite points.");
  return points;
}

}  // namespace dlo
