/// \file ground_surface.h
/// \brief The ground under and around the vehicle in one scan's height grid: a robust
/// low-order surface fit of the lowest cells, and the cells that lie on it.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "dlo/core/height_grid.h"

namespace dlo {

/// A cell of the ground: its centre and mean height in the grid frame, metres.
struct GroundCell {
  float x = 0.0f;
  float y = 0.0f;
  float h = 0.0f;
};

/// Where the ground is looked for and how closely a cell must follow it.
struct GroundSurfaceParams {
  double min_range = 2.0;   ///< metres from the grid's origin; nearer cells are the vehicle's own
  double max_range = 20.0;  ///< metres; farther ground is too sparse and too far from a plane
  /// Metres: a cell within this of the fitted surface is ground. A kerb (0.13 m) stays in, a
  /// car's bonnet or a wall's foot cell (half wall) falls out.
  double band = 0.15;
  int min_cells = 50;  ///< fewer ground cells than this: no ground found
  /// Ground cells kept, thinned evenly beyond it: a few hundred hold z, roll and pitch to
  /// millimetres and milliradians, and each costs a sample of the reference.
  int max_cells = 400;
};

/// The ground of one grid, z = c0 + c1 x + c2 y + c3 x^2 + c4 x y + c5 y^2 (x, y in units of
/// 10 m, for conditioning), and the measured cells on it.
struct GroundSurface {
  bool found = false;
  Eigen::Matrix<double, 6, 1> coefficients = Eigen::Matrix<double, 6, 1>::Zero();
  /// Measured cells within `band` of the surface, at most max_cells (evenly thinned).
  std::vector<GroundCell> cells;
  /// Height of the surface at (x, y), metres.
  double heightAt(double x, double y) const;
};

/// Finds the ground in `grid` (measured cells only, within [min_range, max_range] of the grid's
/// origin). The ground is the lowest extended surface: a plane is started at a low quantile of
/// the nearest cells' heights, fitted to the cells near it and grown outwards into a quadratic
/// surface (a crest or a dip within max_range), each pass keeping only the cells close to the
/// previous one, so that cars, walls, bushes and canopies (all above it) are left out. In place,
/// reusing `out`'s memory. out.found is false where fewer than min_cells cells lie on it.
void fitGroundSurface(const HeightGrid& grid, const GroundSurfaceParams& params,
                      GroundSurface& out);

}  // namespace dlo
