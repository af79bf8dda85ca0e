// Casting one LiDAR ray into the world: ground, static objects and moving cars.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dlo/sim/object_grid.h"
#include "dlo/sim/procedural_world.h"

namespace dlo::sim {

/// Finds the first surface a ray meets; stateless, so one instance serves all threads.
class RayCaster {
 public:
  explicit RayCaster(const ProceduralWorld& world) : world_(world) {}

  /**
   * Closest hit within (0, maxRange] of the ray origin + t * dir (dir of unit length).
   * `dynamic` holds the moving cars at the ray's time; `scratch` is per thread.
   */
  RayHit cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double maxRange,
              const std::vector<Primitive>& dynamic, GridScratch& scratch) const;

 private:
  const ProceduralWorld& world_;
};

}  // namespace dlo::sim
