#include "dlo/eval/axis_ticks.h"

#include <cmath>
#include <cstdio>

namespace dlo::eval {

double niceTickStep(double lo, double hi, int max_ticks) {
  const double range = hi - lo;
  if (!(range > 0.0) || !std::isfinite(range) || max_ticks < 2) return 1.0;
  // Start one decade below the rough step so that the 1-2-5 search finds the smallest fit.
  const double rough = range / (max_ticks - 1);
  double decade = std::pow(10.0, std::floor(std::log10(rough)) - 1.0);
  while (true) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double step = m * decade;
      const double count = std::floor(hi / step) - std::ceil(lo / step) + 1.0;
      if (count <= max_ticks) return step;
    }
    decade *= 10.0;
  }
}

std::vector<double> niceTicks(double lo, double hi, int max_ticks) {
  std::vector<double> ticks;
  if (!(hi > lo)) return ticks;
  const double step = niceTickStep(lo, hi, max_ticks);
  // A small tolerance keeps the ends when lo or hi are themselves multiples of the step.
  const double eps = 1e-9 * step;
  for (double k = std::ceil((lo - eps) / step); k * step <= hi + eps; k += 1.0) {
    ticks.push_back(k * step);
  }
  return ticks;
}

std::string tickLabel(double value, double step) {
  int decimals = 0;
  if (step > 0.0 && std::isfinite(step)) {
    // Steps 0.5 or 0.25 need 1 or 2 decimals: count until the step is a whole number.
    double s = step;
    while (decimals < 9 && std::fabs(s - std::round(s)) > 1e-6 * s) {
      s *= 10.0;
      ++decimals;
    }
  }
  if (std::fabs(value) < 0.5 * std::pow(10.0, -decimals)) value = 0.0;
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

}  // namespace dlo::eval
