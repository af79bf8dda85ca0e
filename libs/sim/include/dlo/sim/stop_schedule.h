// Hard stops on a drive: braking to a standstill, waiting, driving on.
#pragma once

#include <functional>
#include <vector>

namespace dlo::sim {

/// When and how hard the vehicle stops.
struct StopParams {
  double first = 6.0;      ///< Drive time at which the first stop starts braking [s].
  double interval = 12.0;  ///< From the start of one stop to the start of the next [s].
  double braking = 7.0;    ///< Deceleration to the standstill [m/s^2] (a hard stop).
  double wait = 2.0;       ///< Time at a standstill [s].
  double accel = 2.5;      ///< Acceleration back to the route's speed [m/s^2].
};

/**
 * Stops laid over a route's timing: the path stays the same, only how fast it is covered
 * changes. Drive time t maps to route time tau with a rate dtau/dt in [0, 1], so the speed and
 * the yaw rate are the route's times the rate, and the attitude and position at any moment are
 * those the route has at tau. At each stop the rate ramps from 1 to 0 over v0 / braking (v0:
 * the route's speed where the stop starts), stays 0 for `wait`, and ramps back to 1 over
 * v0 / accel: where the route keeps its speed over the stop (the straights), the vehicle
 * decelerates at exactly `braking` and accelerates at `accel`.
 */
class StopSchedule {
 public:
  /// No stops: the route's own timing.
  StopSchedule() = default;
  /**
   * Stops starting at `first` and then every `interval` [s] of drive time up to `until` (a stop
   * due before the one before it has ended starts at that end, and the next count from it).
   * @param routeSpeed  the route's speed at a route time [m/s] (only called here).
   * @throws std::invalid_argument if a parameter is not positive and finite (first and wait
   * may be 0).
   */
  StopSchedule(const StopParams& params, double until,
               const std::function<double(double)>& routeSpeed);

  /// Route time at drive time t [s], and its rate dtau/dt in [0, 1].
  double routeTime(double t, double& rate) const;
  /// True without stops.
  bool empty() const { return stops_.empty(); }

 private:
  struct Stop {
    double t0 = 0.0;     ///< Drive time where braking starts [s].
    double tau0 = 0.0;   ///< Route time there [s].
    double brake = 0.0;  ///< Durations of the braking, the standstill and the acceleration [s].
    double wait = 0.0;
    double accel = 0.0;
    double end() const { return t0 + brake + wait + accel; }
  };
  std::vector<Stop> stops_;
};

}  // namespace dlo::sim
