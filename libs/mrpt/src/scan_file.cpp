#include "dlo/mrpt/scan_file.h"

#include <algorithm>
#include <cctype>
#include <fstream>

#include "dlo/files/error.h"
#include "dlo/formats/kitti_bin.h"
#include "dlo/formats/ply_file.h"
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
