#include "dlo/metrics/error_statistics.h"

#include <algorithm>
#include <cmath>

namespace dlo::metrics {

ErrorStatistics errorStatistics(std::vector<double> errors) {
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) return s;
  double sum = 0.0, sum_sq = 0.0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
    s.max = std::max(s.max, e);
  }
  const double n = static_cast<double>(errors.size());
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  const size_t mid = errors.size() / 2;
  std::nth_element(errors.begin(), errors.begin() + mid, errors.end());
  s.median = errors[mid];
  if (errors.size() % 2 == 0) {
    s.median = 0.5 * (s.median + *std::max_element(errors.begin(), errors.begin() + mid));
  }
  return s;
}

}  // namespace dlo::metrics
