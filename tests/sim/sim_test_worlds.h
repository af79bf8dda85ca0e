// Small hand-made worlds for the simulator tests, where every surface is known.
#pragma once

#include <vector>

#include "dlo/sim/procedural_world.h"

namespace dlo::sim::test {

/// Flat ground at z = 0 without roads, tabulated around the origin.
inline TerrainParams flatGround() {
  TerrainParams p;
  p.gridMin = {-150.0, -150.0};
  p.gridMax = {150.0, 150.0};
  return p;
}

/// Flat ground and the given objects, no traffic.
inline ProceduralWorld worldWith(std::vector<Primitive> objects,
                                 const TerrainParams& ground = flatGround()) {
  return ProceduralWorld(Terrain(ground), std::move(objects), Traffic());
}

}  // namespace dlo::sim::test
