#include "dlo/bench/bench_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <sstream>

#include "dlo/metrics/absolute_trajectory_error.h"
#include "dlo/metrics/kitti_drift.h"
#include "dlo/metrics/timestamp_matching.h"

namespace dlo::bench {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Nearest-rank percentile, as slam_report.json uses.
double percentile(std::vector<double> v, double q) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const size_t i = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(i == 0 ? 0 : i - 1, v.size() - 1)];
}

std::string fixed(double x, int decimals, const char* missing) {
  if (!std::isfinite(x)) return missing;
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", decimals, x);
  return text;
}

/// CSV cell: quoted when it holds a separator or a quote.
std::string csvCell(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

MethodRow evaluateRun(const MethodRun& run, const std::string& preprocessing,
                      const metrics::Trajectory& ground_truth, size_t first_frames) {
  MethodRow row;
  row.method = run.method;
  row.preprocessing = preprocessing;
  row.peak_memory_mb = run.peak_memory_mb;
  row.error = run.error;
  row.ate_rmse = row.drift_percent = kNaN;
  const size_t n = std::min({first_frames, run.ms.size(), run.trajectory.size()});
  row.frames = n;
  const std::vector<double> ms(run.ms.begin(), run.ms.begin() + static_cast<long>(n));
  row.ms_median = percentile(ms, 0.5);
  row.ms_p95 = percentile(ms, 0.95);
  const double total_ms = std::accumulate(ms.begin(), ms.end(), 0.0);
  row.frames_per_s = total_ms > 0.0 ? 1000.0 * static_cast<double>(n) / total_ms : kNaN;

  if (ground_truth.empty()) return row;
  metrics::Trajectory estimate;
  for (size_t i = 0; i < n; ++i)
    estimate.push_back(run.trajectory.times[i], run.trajectory.poses[i]);
  const auto [matched, reference] = metrics::matchedTrajectories(estimate, ground_truth, 0.005);
  if (matched.size() < 3) {
    if (row.error.empty()) {
      row.error = "only " + std::to_string(matched.size()) +
                  " poses match the ground truth by timestamp (within 5 ms).";
    }
    return row;
  }
  row.ate_rmse =
      metrics::absoluteTrajectoryError(matched, reference, metrics::Alignment::kUmeyama).error.rmse;
  const metrics::KittiDriftResult drift = metrics::kittiDrift(matched, reference);
  if (drift.segments > 0) row.drift_percent = drift.translation_percent;
  std::ostringstream lengths;
  for (size_t i = 0; i < drift.per_length.size(); ++i) {
    lengths << (i ? ", " : "") << fixed(drift.per_length[i].length, 0, "?");
  }
  row.drift_lengths = lengths.str() + " m";
  return row;
}

std::string tableCsv(const std::vector<MethodRow>& rows) {
  std::ostringstream o;
  o << "method,preprocessing,frames,ms_median,ms_p95,frames_per_s,ate_m,drift_percent,"
       "peak_memory_mb\n";
  for (const MethodRow& r : rows) {
    o << csvCell(r.method) << "," << csvCell(r.preprocessing) << "," << r.frames << ","
      << fixed(r.ms_median, 3, "") << "," << fixed(r.ms_p95, 3, "") << ","
      << fixed(r.frames_per_s, 2, "") << "," << fixed(r.ate_rmse, 4, "") << ","
      << fixed(r.drift_percent, 3, "") << "," << fixed(r.peak_memory_mb, 1, "") << "\n";
  }
  return o.str();
}

std::string tableMarkdown(const std::vector<MethodRow>& rows) {
  std::ostringstream o;
  o << "| method | preprocessing | frames | ms/frame median | p95 | frames/s | ATE m | drift % | "
       "peak memory MB |\n";
  o << "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const MethodRow& r : rows) {
    o << "| " << r.method << " | " << r.preprocessing << " | " << r.frames << " | "
      << fixed(r.ms_median, 2, "n/a") << " | " << fixed(r.ms_p95, 2, "n/a") << " | "
      << fixed(r.frames_per_s, 1, "n/a") << " | " << fixed(r.ate_rmse, 3, "n/a") << " | "
      << fixed(r.drift_percent, 2, "n/a") << " | " << fixed(r.peak_memory_mb, 0, "n/a") << " |\n";
  }
  return o.str();
}

}  // namespace dlo::bench
