/// \file grid_geometry.h
/// \brief Placement of a regular 2D grid in the plane: origin, cell size, dimensions.
#pragma once

#include <cmath>

namespace dlo {

/// Where a 2D grid lies in metric space. Cell (row r, col c) covers
/// x in [x_min + c*resolution, x_min + (c+1)*resolution) and likewise y with rows.
/// Continuous cell coordinates: u = (x - x_min)/resolution, v = (y - y_min)/resolution;
/// the centre of cell (r, c) is at (u, v) = (c + 0.5, r + 0.5).
struct GridGeometry {
  double x_min = -20.0;     ///< metres, left edge of column 0
  double y_min = -20.0;     ///< metres, bottom edge of row 0
  double resolution = 0.1;  ///< metres per cell side
  int cols = 400;           ///< cells along x
  int rows = 400;           ///< cells along y

  /// A cols x rows grid of the given resolution centred on the origin (the sensor).
  static GridGeometry centred(int cols, int rows, double resolution) {
    return GridGeometry{-0.5 * cols * resolution, -0.5 * rows * resolution, resolution, cols, rows};
  }

  /// Geometry of the next coarser level: cells twice as large, same origin.
  GridGeometry coarser() const {
    return GridGeometry{x_min, y_min, 2.0 * resolution, (cols + 1) / 2, (rows + 1) / 2};
  }

  int cellCount() const { return cols * rows; }
  double u(double x) const { return (x - x_min) / resolution; }
  double v(double y) const { return (y - y_min) / resolution; }
  double cellCentreX(int col) const { return x_min + (col + 0.5) * resolution; }
  double cellCentreY(int row) const { return y_min + (row + 0.5) * resolution; }
};

}  // namespace dlo
