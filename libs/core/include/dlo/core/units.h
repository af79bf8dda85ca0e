/// \file units.h
/// \brief Unit conversions shared by the libraries, apps and tests.
#pragma once

#include <cmath>

namespace dlo {

/// Radians per degree: `angle_deg * kDeg` is in radians, `angle_rad / kDeg` in degrees.
inline constexpr double kDeg = M_PI / 180.0;

}  // namespace dlo
