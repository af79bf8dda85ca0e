#include "dlo/core/ring_count.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace dlo {

namespace {
constexpr double kBinDeg = 0.05;
constexpr double kMaxElevationDeg = 45.0;  // Ouster OS0 reaches +-45 deg
constexpr int kBins = static_cast<int>(2.0 * kMaxElevationDeg / kBinDeg);
constexpr float kMinRange = 3.0f;
constexpr float kMaxRange = 120.0f;
}  // namespace

RingEstimate estimateRings(const PointCloud& points, const Eigen::Isometry3f& to_sensor) {
  std::vector<size_t> histogram(kBins, 0);
  RingEstimate e;
  constexpr double kToBin = 180.0 / M_PI / kBinDeg;
  for (const Eigen::Vector3f& vehicle : points) {
    const Eigen::Vector3f p = to_sensor * vehicle;
    const float r = std::hypot(p.x(), p.y());
    if (!(r >= kMinRange && r <= kMaxRange) || !std::isfinite(p.z())) continue;
    const int bin = static_cast<int>(
        std::floor(std::atan2(static_cast<double>(p.z()), r) * kToBin + kBins / 2.0));
    if (bin < 0 || bin >= kBins) continue;
    ++histogram[bin];
    ++e.points;
  }
  if (e.points == 0) return e;
  // A tooth's bins hold at least a fifth of the mean count per bin over the occupied span (a
  // ring one bin wide holds span / rings times the mean: 8 for an HDL-64, 37 for a VLP-16).
  int lo = 0, hi = kBins - 1;
  while (histogram[lo] == 0) ++lo;
  while (histogram[hi] == 0) --hi;
  const double span_bins = hi - lo + 1;
  const size_t threshold =
      std::max<size_t>(2, static_cast<size_t>(0.2 * static_cast<double>(e.points) / span_bins));
  // Teeth: runs of bins at or above the threshold; each one's centre of mass is its elevation.
  std::vector<double> centres;
  size_t on = 0;
  int covered = 0;
  for (int b = lo; b <= hi;) {
    if (histogram[b] < threshold) {
      ++b;
      continue;
    }
    double mass = 0.0, moment = 0.0;
    while (b <= hi && histogram[b] >= threshold) {
      mass += static_cast<double>(histogram[b]);
      moment += static_cast<double>(histogram[b]) * b;
      ++b;
      ++covered;
    }
    on += static_cast<size_t>(mass);
    centres.push_back(moment / mass);
  }
  e.rings = static_cast<int>(centres.size());
  e.on_rings = static_cast<double>(on) / static_cast<double>(e.points);
  e.coverage = covered / span_bins;
  if (centres.size() >= 2) {
    std::vector<double> steps;
    for (size_t i = 1; i < centres.size(); ++i)
      steps.push_back((centres[i] - centres[i - 1]) * kBinDeg);
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    e.spacing_deg = steps[steps.size() / 2];
  }
  return e;
}

}  // namespace dlo
