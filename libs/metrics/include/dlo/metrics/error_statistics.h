/// \file error_statistics.h
/// \brief RMSE, mean, median and maximum of a set of errors.
#pragma once

#include <cstddef>
#include <vector>

namespace dlo::metrics {

/// Summary of non-negative errors (all zero when there are none).
struct ErrorStatistics {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double max = 0.0;
  size_t count = 0;
};

/// Statistics of `errors` (the median of an even count is the mean of the two middle values).
ErrorStatistics errorStatistics(std::vector<double> errors);

}  // namespace dlo::metrics
