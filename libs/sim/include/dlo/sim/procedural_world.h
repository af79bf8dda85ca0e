// The procedural outdoor world: a small town on rolling hills, generated from a seed.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dlo/sim/object_grid.h"
#include "dlo/sim/primitives.h"
#include "dlo/sim/terrain.h"
#include "dlo/sim/traffic.h"

namespace dlo::sim {

/// Layout of the generated town; lengths in metres.
struct WorldParams {
  /// Road centrelines run along these x (north-south roads) and y (east-west roads).
  std::vector<double> roadsX{-120.0, -60.0, 0.0, 60.0, 120.0, 180.0};
  std::vector<double> roadsY{-80.0, -40.0, 0.0, 40.0, 80.0, 120.0};
  /// The block the vehicle drives around: between roadsX[2..3] and roadsY[2..3].
  Eigen::Vector2d loopMin{0.0, 0.0}, loopMax{60.0, 40.0};
  double roadExtension = 30.0;  ///< Roads continue this far beyond the outer crossings.
  double gridMargin = 140.0;    ///< Ground tabulated this far around the loop block.
  double hillAmplitude = 1.2;   ///< Largest hill wave [m]; the ground grade stays a few %.
  double objectCellSize = 4.0;  ///< Cell of the object grid.
};

/**
 * Ground, static objects (buildings, trees, poles, bushes, parked cars) and moving cars.
 *
 * Built either by generate() from a seed (the same seed always gives the same world) or from
 * explicit parts, which tests use to place known objects.
 */
class ProceduralWorld {
 public:
  ProceduralWorld(Terrain terrain, std::vector<Primitive> objects, Traffic traffic,
                  double cellSize = 4.0);

  /// The procedural town for `seed`.
  static ProceduralWorld generate(uint32_t seed, const WorldParams& params = WorldParams());

  const Terrain& terrain() const { return terrain_; }
  const ObjectGrid& objects() const { return objects_; }
  const Traffic& traffic() const { return traffic_; }

 private:
  Terrain terrain_;
  ObjectGrid objects_;
  Traffic traffic_;
};

}  // namespace dlo::sim
