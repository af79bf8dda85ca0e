// The procedural outdoor worlds generated from a seed: a small town on rolling hills, an open road.
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
  /// > 0: steep hills instead, whose grade (with the road's crown) stays within it everywhere
  /// and comes close to it on the loop's straights, with crests and dips (see steepHills()).
  double maxGrade = 0.0;
  double objectCellSize = 4.0;  ///< Cell of the object grid.
  /// 0: the parked and moving cars come with the town's seed. Otherwise they are drawn from this
  /// seed instead, and the rest of the town (ground, buildings, trees, poles, bushes) stays the
  /// seed's: another day in the same streets, for localising on a map of the first.
  uint32_t trafficSeed = 0;
};

/// Layout of the open road: long roads through open land with little beside them; metres.
struct OpenRoadParams {
  /// The roads run along the sides of this rectangle (and 30 m beyond its corners); the drive
  /// goes round it counter-clockwise from the middle of its south side, heading east, so that
  /// its first 585 m are one straight.
  Eigen::Vector2d loopMin{-600.0, 0.0}, loopMax{600.0, 150.0};
  double cruise = 15.0;         ///< Speed of the drive on the straights [m/s].
  double poleSpacing = 60.0;    ///< Mean gap between the poles on the roads' outer side.
  double copseSpacing = 200.0;  ///< Mean gap between clumps of trees and bushes off the road.
  double gridMargin = 140.0;    ///< Ground tabulated this far around the rectangle.
  double hillAmplitude = 1.2;   ///< As WorldParams::hillAmplitude: flat-ish land.
  double maxGrade = 0.0;        ///< As WorldParams::maxGrade.
  double objectCellSize = 8.0;  ///< Cell of the object grid.
};

/**
 * Hill waves whose grade, with the road's crown added, stays within `maxGrade` everywhere:
 * 80 % of the grade budget goes to a wave along x of 48-62 m wavelength (each of the town
 * loop's east-west straights spans half a wavelength, so the drive climbs and descends at
 * about 0.75 maxGrade between crests and dips), 15 % to one along y and the rest to a short
 * wave in a random direction. Deterministic per seed.
 * @throws std::invalid_argument if maxGrade does not exceed the crown's own grade.
 */
std::vector<HillWave> steepHills(double maxGrade, const TerrainParams& ground, uint32_t seed);

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
  /**
   * The open road for `seed`: the roads (with kerbs) through grass, a pole every ~60 m on
   * their outer side and a clump of trees and bushes every ~200 m, 10-40 m off the road; no
   * buildings, no parked cars, no traffic. Scans there constrain little along the road.
   */
  static ProceduralWorld generateOpenRoad(uint32_t seed,
                                          const OpenRoadParams& params = OpenRoadParams());

  const Terrain& terrain() const { return terrain_; }
  const ObjectGrid& objects() const { return objects_; }
  const Traffic& traffic() const { return traffic_; }

 private:
  Terrain terrain_;
  ObjectGrid objects_;
  Traffic traffic_;
};

}  // namespace dlo::sim
