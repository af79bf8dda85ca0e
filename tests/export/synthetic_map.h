/// \file synthetic_map.h
/// \brief A small SlamMap with known content for the export tests.
#pragma once

#include "dlo/slam/slam_map.h"

namespace dlo::test {

/// Geometry of the synthetic world: flat ground at z = 0 and a box on it.
struct SyntheticWorld {
  static constexpr double kRadius = 15.0;  ///< keyframes lie on this circle, metres
  static constexpr double kBoxX = 0.0;     ///< box centre = circle centre
  static constexpr double kBoxY = 15.0;
  static constexpr double kBoxHalfSide = 2.0;  ///< metres
  static constexpr double kBoxHeight = 2.0;    ///< metres
  static constexpr int kKeyframes = 10;
  static constexpr int kFramesPerKeyframe = 2;
};

/// 10 keyframes on a circle around the box (keyframe 0 at the identity, heading along +x, so
/// the circle is centred at (0, 15)), each seeing the world within 20 m as voxel centroids in its
/// vehicle frame; 20 frames (two per keyframe); 9 odometry edges and one loop edge 9 -> 0 with
/// information diag(100, 200, 300, 400, 500, 600).
SlamMap makeSyntheticMap();

}  // namespace dlo::test
