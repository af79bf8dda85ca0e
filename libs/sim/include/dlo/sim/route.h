// The path the vehicle drives and its speed along it.
#pragma once

#include <Eigen/Core>
#include <vector>

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
 * A closed loop of straight lines and circular arcs, driven lap after lap counter-clockwise.
 * The speed comes from a profile that slows down for turns within acceleration limits, so that
 * speed is continuous and the vehicle is back at the start after every lap.
 */
class Route {
 public:
  /// Around the rectangle [lo, hi] with corners rounded to `radius`, starting at the middle of
  /// the lower (south) side heading east (+x).
  static Route roundedRectangle(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double radius,
                                const SpeedLimits& limits = SpeedLimits());

  /// State at time t >= 0 [s].
  RouteState stateAt(double t) const;
  /// Length of one lap [m].
  double lapLength() const { return length_; }
  /// Duration of one lap [s].
  double lapDuration() const { return times_.back(); }

 private:
  struct Piece {
    Eigen::Vector2d start;   ///< Lines: start point; arcs: centre.
    double heading0 = 0.0;   ///< Heading at the piece's start.
    double curvature = 0.0;  ///< 0 for lines, 1 / radius for (left) arcs.
    double s0 = 0.0, length = 0.0;
  };
  void geometryAt(double s, Eigen::Vector2d& position, double& heading, double& curvature) const;
  void buildSpeedProfile(const SpeedLimits& limits);

  std::vector<Piece> pieces_;
  double length_ = 0.0;
  double ds_ = 0.25;
  std::vector<double> speeds_, times_;  ///< At s = k * ds_, k = 0..n (n * ds_ = length).
};

}  // namespace dlo::sim
