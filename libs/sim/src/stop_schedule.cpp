#include "dlo/sim/stop_schedule.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dlo::sim {

StopSchedule::StopSchedule(const StopParams& p, double until,
                           const std::function<double(double)>& routeSpeed) {
  const auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  const auto nonNegative = [](double v) { return v >= 0.0 && std::isfinite(v); };
  if (!nonNegative(p.first) || !positive(p.interval) || !positive(p.braking) ||
      !nonNegative(p.wait) || !positive(p.accel))
    throw std::invalid_argument("StopSchedule: the stop parameters must be positive and finite");
  for (double t = p.first; t < until; t += p.interval) {
    Stop s;
    s.t0 = stops_.empty() ? t : std::max(t, stops_.back().end());
    if (s.t0 >= until) break;
    double rate;
    s.tau0 = routeTime(s.t0, rate);
    const double v0 = routeSpeed(s.tau0);
    s.brake = v0 / p.braking;
    s.wait = p.wait;
    s.accel = v0 / p.accel;
    stops_.push_back(s);
    t = s.t0;
  }
}

double StopSchedule::routeTime(double t, double& rate) const {
  rate = 1.0;
  const auto next = std::upper_bound(stops_.begin(), stops_.end(), t,
                                     [](double v, const Stop& s) { return v < s.t0; });
  if (next == stops_.begin()) return t;
  const Stop& s = *(next - 1);
  // Route time gained in each phase: a linear ramp of the rate covers half its duration.
  double u = t - s.t0;
  if (u < s.brake) {
    rate = 1.0 - u / s.brake;
    return s.tau0 + u - 0.5 * u * u / s.brake;
  }
  const double braked = s.tau0 + 0.5 * s.brake;
  u -= s.brake;
  if (u < s.wait) {
    rate = 0.0;
    return braked;
  }
  u -= s.wait;
  if (u < s.accel) {
    rate = u / s.accel;
    return braked + 0.5 * u * u / s.accel;
  }
  return braked + 0.5 * s.accel + (u - s.accel);
}

}  // namespace dlo::sim
