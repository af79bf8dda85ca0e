// The vehicle's 6-DoF pose over time: the route in the plane, attitude from the ground.
#pragma once

#include <Eigen/Geometry>

#include "dlo/sim/route.h"
#include "dlo/sim/terrain.h"

namespace dlo::sim {

/// Where the wheels and the LiDAR are, in the vehicle frame (x forward, y left, z up, origin
/// on the ground below the centre of the wheelbase).
struct VehicleGeometry {
  double wheelbase = 2.7;                         ///< [m]
  double track = 1.6;                             ///< [m]
  Eigen::Vector3d sensorPosition{0.3, 0.0, 1.8};  ///< LiDAR on the roof rack [m].
};

/**
 * Ground-truth pose of the vehicle: x, y and heading from the Route; height, roll and pitch
 * from the terrain under the four wheels, so that the attitude follows slopes and the road
 * crown the way a car's suspension would let it.
 */
class VehicleTrajectory {
 public:
  VehicleTrajectory(const Route& route, const Terrain& terrain,
                    const VehicleGeometry& geometry = VehicleGeometry());

  /// Pose of the vehicle frame in the world at time t [s].
  Eigen::Isometry3d vehiclePose(double t) const;
  /// Mounting pose of the LiDAR in the vehicle frame.
  Eigen::Isometry3d sensorMount() const;

  const Route& route() const { return route_; }
  const VehicleGeometry& geometry() const { return geometry_; }

 private:
  const Route& route_;
  const Terrain& terrain_;
  VehicleGeometry geometry_;
};

}  // namespace dlo::sim
