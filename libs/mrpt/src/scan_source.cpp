#include "dlo/mrpt/scan_source.h"

#include <sstream>

namespace dlo {

std::string describeScanSourceStats(const ScanSourceStats& stats) {
  std::ostringstream s;
  s << "entries read: " << stats.entries_read << ", scans: " << stats.scans << "\n";
  if (stats.skipped_by_label > 0) {
    s << "skipped (other sensor label): " << stats.skipped_by_label << "\n";
  }
  for (const auto& [cls, count] : stats.skipped_by_class) {
    s << "skipped " << cls << ": " << count;
    const auto why = stats.skip_reasons.find(cls);
    s << (why != stats.skip_reasons.end() ? " (" + why->second + ")" : " (not a point cloud)")
      << "\n";
  }
  if (stats.empty_scans > 0) s << "empty scans (no point left): " << stats.empty_scans << "\n";
  if (stats.dropped_non_finite > 0) {
    s << "points dropped, non-finite: " << stats.dropped_non_finite << "\n";
  }
  if (stats.dropped_by_range > 0) {
    s << "points dropped, out of range: " << stats.dropped_by_range << "\n";
  }
  if (!stats.error.empty()) s << "error: " << stats.error << "\n";
  return s.str();
}

}  // namespace dlo
