/// \file axis_ticks.h
/// \brief Round tick positions (1, 2 or 5 times a power of ten) and their labels.
#pragma once

#include <string>
#include <vector>

namespace dlo::eval {

/// The spacing of ticks covering [lo, hi] with at most `max_ticks` ticks: 1, 2 or 5 times a
/// power of ten (the smallest such spacing that fits). Returns 1 for an empty or invalid range.
double niceTickStep(double lo, double hi, int max_ticks);

/// The multiples of niceTickStep() inside [lo, hi], increasing.
std::vector<double> niceTicks(double lo, double hi, int max_ticks);

/// A tick value as text with just enough decimals for `step` ("0.5", "10", "-2.25"); values that
/// are zero up to rounding print as "0", never "-0".
std::string tickLabel(double value, double step);

}  // namespace dlo::eval
