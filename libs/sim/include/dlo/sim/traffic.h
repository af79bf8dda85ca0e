// Cars: the shape of one car, and the cars that drive along the roads (dynamic outliers).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dlo/sim/primitives.h"
#include "dlo/sim/terrain.h"

namespace dlo::sim {

/// Appends the two boxes of a passenger car (body 4.5 x 1.8 x 0.75 m on 0.25 m of ground
/// clearance, cabin 2.5 x 1.6 x 0.5 m) standing at `ground` and heading `yaw`.
void appendCarPrimitives(const Eigen::Vector3d& ground, double yaw, SurfaceClass surface,
                         std::vector<Primitive>& out);

/// Appends the two boxes of a box truck (cargo box 7.5 x 2.5 x 2.8 m on 0.8 m of clearance,
/// cab 2.2 x 2.4 x 2.1 m ahead of it; 10 m long overall) standing at `ground` and heading `yaw`.
void appendTruckPrimitives(const Eigen::Vector3d& ground, double yaw, SurfaceClass surface,
                           std::vector<Primitive>& out);

/// A car driving at constant speed along a straight road, wrapping around at its end.
struct MovingCar {
  Eigen::Vector2d start;      ///< Start of the lane's centreline.
  Eigen::Vector2d direction;  ///< Unit vector of travel.
  double length = 100.0;      ///< Lane length before the car wraps to the start [m].
  double speed = 8.0;         ///< [m/s]
  double phase = 0.0;         ///< Distance from start at t = 0 [m].
  bool truck = false;         ///< A box truck instead of a passenger car.
};

/// All moving cars; their position is a function of time only.
class Traffic {
 public:
  Traffic() = default;
  explicit Traffic(std::vector<MovingCar> cars) : cars_(std::move(cars)) {}

  /// The car primitives at time t [s], standing on the terrain; only the cars whose centre
  /// is within `radius` of `near` (culling for one sensor position).
  void primitivesAt(double t, const Terrain& terrain, const Eigen::Vector2d& near, double radius,
                    std::vector<Primitive>& out) const;

  const std::vector<MovingCar>& cars() const { return cars_; }

 private:
  std::vector<MovingCar> cars_;
};

}  // namespace dlo::sim
