// Internal to dlo_slam: when two answers of a search (the localiser's global search, a loop
// closure's lattice of starts) lie in different basins.
#pragma once

#include "dlo/core/units.h"

namespace dlo {

/// Two search results farther apart than this, in position, lie in different basins (metres).
inline constexpr double kDistinctBasin = 1.5;
/// ... or in heading (radians).
inline constexpr double kDistinctBasinAngle = 5.0 * kDeg;

}  // namespace dlo
