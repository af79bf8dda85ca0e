// The path the vehicle drives and its speed along it.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dlo/sim/stop_schedule.h"

namespace dlo::sim {

/// Planar state of the vehicle on its route.
struct RouteState {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double heading = 0.0;   ///< [rad], counter-clockwise from +x.
  double speed = 0.0;     ///< [m/s]
  double yawRate = 0.0;   ///< [rad/s]
  double distance = 0.0;  ///< Travelled since t = 0 [m].
};

/// Limits of the speed profile.
struct SpeedLimits {
  double cruise = 10.0;            ///< Top speed on straights [m/s].
  double lateralAccel = 3.5;       ///< Caps the speed in turns: v^2 * curvature [m/s^2].
  double longitudinalAccel = 2.0;  ///< Braking and acceleration [m/s^2].
};

/**
 * A closed loop of straight lines and corners, driven lap after lap counter-clockwise.
 * Each corner is clothoid-arc-clothoid: the curvature ramps linearly from 0 to 1 / radius, stays
 * there, and ramps back, so the yaw rate builds up over about a second as a steered car's does
 * rather than stepping at the corner (a step no real vehicle makes, and one that would break
 * constant-velocity deskewing at every turn in a way real data does not).
 * The speed comes from a profile that slows down for turns within acceleration limits, so that
 * speed is continuous and the vehicle is back at the start after every lap.
 */
class Route {
 public:
  /**
   * Around the rectangle [lo, hi], starting at the middle of the lower (south) side heading east
   * (+x). The route passes through the middle of every side and turns each corner by 90 deg.
   *
   * @param radius            Radius of the constant-curvature part of each corner [m], > 0.
   * @param transitionLength  Length of each clothoid (Euler spiral) over which the curvature
   *                          ramps between 0 and 1 / radius [m]. Clamped to [0, radius * pi / 2]
   *                          (at the upper bound the arc vanishes; 0 gives circular corners).
   * @param limits            Speed profile limits.
   * @throws std::invalid_argument if radius is not positive and finite, transitionLength is NaN or
   * a corner does not fit in half a side.
   */
  static Route roundedRectangle(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double radius,
                                double transitionLength = 8.0,
                                const SpeedLimits& limits = SpeedLimits());

  /**
   * A robot's patrol around the rectangle [lo, hi]: from the middle of the lower (south) side
   * heading east, it drives 10 m, turns round on the spot, drives back, turns round again, and
   * then drives round the rectangle counter-clockwise, stopping at each vertex (a crossing of
   * the procedural town's roads) to turn 90 deg on the spot. Straights at `speed` with
   * `accel` ramps; turns on the spot at `yawRateDeg`, the yaw rate stepping from zero to it and
   * back, as a robot's (or a handheld rig's) does. Closed: the lap ends where it began.
   * @throws std::invalid_argument if speed, yawRateDeg or accel is not positive and finite, or
   * the rectangle's lower side is shorter than 20 m.
   */
  static Route patrol(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double speed,
                      double yawRateDeg, double accel = 1.0);

  /**
   * Hard stops on the drive (see StopSchedule) up to `until` [s]; replaces any set before.
   * @throws std::invalid_argument for parameters that are not positive and finite.
   */
  void setStops(const StopParams& params, double until);

  /// State at time t >= 0 [s].
  RouteState stateAt(double t) const;
  /// Length of one lap [m].
  double lapLength() const { return length_; }
  /// Duration of one lap [s].
  double lapDuration() const { return times_.back(); }

 private:
  /// Geometry at one arc length; the heading is unwrapped (0 .. 2 pi over a lap).
  struct Sample {
    Eigen::Vector2d position = Eigen::Vector2d::Zero();
    double heading = 0.0;
    double curvature = 0.0;
  };
  void geometryAt(double s, Eigen::Vector2d& position, double& heading, double& curvature) const;
  void buildSpeedProfile(const SpeedLimits& limits);
  /// State at route time tau, without the stops.
  RouteState routeStateAt(double tau) const;
  StopSchedule stops_;

  /// One piece of a patrol: a straight drive or a turn on the spot.
  struct Piece {
    double t0 = 0.0, duration = 0.0;  ///< [s]
    Eigen::Vector2d start = Eigen::Vector2d::Zero();
    double heading = 0.0;   ///< at the start [rad]
    double distance = 0.0;  ///< along the heading [m] (0 for a turn)
    double turn = 0.0;      ///< signed angle turned on the spot [rad] (0 for a drive)
    double s0 = 0.0;        ///< distance travelled before the piece [m]
  };
  RouteState patrolStateAt(double tau) const;
  std::vector<Piece> pieces_;  ///< non-empty for a patrol
  double speed_ = 0.0, accel_ = 0.0, yawRate_ = 0.0;

  /// Geometry at s = k * step_, k = 0..n (n * step_ = length_; the last sample closes the lap).
  std::vector<Sample> table_;
  double step_ = 0.05;
  double length_ = 0.0;
  double ds_ = 0.25;
  std::vector<double> speeds_, times_;  ///< At s = k * ds_, k = 0..n (n * ds_ = length).
};

}  // namespace dlo::sim
