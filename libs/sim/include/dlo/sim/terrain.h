// The ground of the procedural world: smooth hills with roads cut into them.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dlo/sim/primitives.h"

namespace dlo::sim {

/// One straight road, given by its centreline.
struct RoadSegment {
  Eigen::Vector2d a, b;
};

/// A plane wave of the hill field: amplitude * sin(2 pi (direction . p) / wavelength + phase).
struct HillWave {
  double amplitude = 0.0;                                ///< [m]
  double wavelength = 100.0;                             ///< [m]
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  ///< Unit vector.
  double phase = 0.0;                                    ///< [rad]
};

/// Shape of the ground; all lengths in metres.
struct TerrainParams {
  std::vector<HillWave> hills;  ///< Empty: flat ground at z = 0.
  std::vector<RoadSegment> roads;
  double roadHalfWidth = 5.0;  ///< Kerb to centreline.
  double crownHeight = 0.04;   ///< Road centre above its edges (water runs off to the kerbs).
  double curbHeight = 0.13;    ///< Step from the road edge up to the sidewalk.
  double sidewalkWidth = 2.5;  ///< Beyond it the ground is grass.
  Eigen::Vector2d gridMin{-200.0, -200.0};  ///< Area where the ground is tabulated; outside it
  Eigen::Vector2d gridMax{200.0, 200.0};    ///< is evaluated exactly (slower).
  double gridResolution = 0.5;
};

/**
 * Height field z = ground(x, y): the hills, with the roads sunk by the curb height and
 * crowned. The hills and the distance to the nearest road centreline are tabulated on a grid
 * and interpolated bilinearly, so that the kerb stays a sharp step where the interpolated
 * distance crosses the road half width.
 */
class Terrain {
 public:
  explicit Terrain(const TerrainParams& params);

  /// Ground height [m].
  double heightAt(double x, double y) const;
  /// Upward unit normal of the smooth ground (hills and crown; kerbs are ignored).
  Eigen::Vector3d normalAt(double x, double y) const;
  /// Road, sidewalk or grass.
  SurfaceClass surfaceAt(double x, double y) const;
  /// Distance to the nearest road centreline [m] (infinite without roads).
  double roadDistance(double x, double y) const;
  /**
   * First t in (0, tmax] where origin + t * dir (unit dir) meets the ground, or a negative
   * value. Marches with steps bounded by the slope of the hills, so that no crossing is
   * skipped, then bisects the last step.
   */
  double intersectRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double tmax) const;

  const TerrainParams& params() const { return params_; }

 private:
  double hillsExact(double x, double y) const;
  double roadDistanceExact(double x, double y) const;
  /// Hills height and road distance, interpolated (or exact outside the grid).
  void sample(double x, double y, double& hills, double& road) const;
  double groundFrom(double hills, double road) const;

  TerrainParams params_;
  int nx_ = 0, ny_ = 0;
  std::vector<float> hills_, road_;
  double slopeBound_ = 0.0;  ///< Bound on |grad| of hills + crown.
};

}  // namespace dlo::sim
