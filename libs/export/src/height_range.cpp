#include "dlo/export/height_range.h"

#include <algorithm>
#include <cmath>

namespace dlo {

std::pair<double, double> colourHeightRange(std::vector<float> heights, double low_percentile,
                                            double high_percentile) {
  if (heights.empty()) return {0.0, 1.0};
  auto at = [&](double p) {
    const double last = static_cast<double>(heights.size() - 1);
    const size_t k = static_cast<size_t>(std::clamp(std::round(p / 100.0 * last), 0.0, last));
    std::nth_element(heights.begin(), heights.begin() + k, heights.end());
    return static_cast<double>(heights[k]);
  };
  double lo = at(low_percentile), hi = at(high_percentile);
  if (hi - lo < 0.05) {
    const auto [mn, mx] = std::minmax_element(heights.begin(), heights.end());
    lo = *mn;
    hi = *mx;
  }
  return {lo, std::max(hi, lo + 1e-3)};
}

}  // namespace dlo
