// A uniform 2D grid over the static objects, so that a ray tests only the objects it passes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dlo/sim/primitives.h"

namespace dlo::sim {

/// Per-thread scratch memory of ObjectGrid::intersect (avoids testing an object twice).
struct GridScratch {
  std::vector<uint32_t> stamp;
  uint32_t counter = 0;
};

/// Result of a ray cast: distance along the ray and what was hit.
struct RayHit {
  double t = -1.0;  ///< Negative: nothing.
  SurfaceClass surface = SurfaceClass::None;
  bool valid() const { return t >= 0.0; }
};

/**
 * Static primitives binned by their horizontal bounding boxes into square cells. A ray walks
 * the cells it crosses in order (Amanatides-Woo) and stops as soon as the next cell starts
 * beyond the best hit, or the ray is above every object still ahead.
 */
class ObjectGrid {
 public:
  ObjectGrid() = default;
  ObjectGrid(std::vector<Primitive> primitives, double cellSize);

  /// Closest hit with t in [tmin, tmax].
  RayHit intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double tmin,
                   double tmax, GridScratch& scratch) const;

  const std::vector<Primitive>& primitives() const { return primitives_; }

 private:
  std::vector<Primitive> primitives_;
  double cell_ = 4.0;
  Eigen::Vector2d min_ = Eigen::Vector2d::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<uint32_t> cellStart_;  ///< CSR offsets into cellItems_, size nx*ny + 1.
  std::vector<uint32_t> cellItems_;
  std::vector<float> cellTop_;  ///< Highest point of any object in the cell.
  std::vector<double> primTop_;
  double globalTop_ = -1e300;
};

}  // namespace dlo::sim
