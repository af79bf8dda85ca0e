/// \file height_map_export.h
/// \brief The map as an MRPT 2.5D height grid (CHeightGridMap2D, `heightmap.bin`).
#pragma once

#include <mrpt/maps/CHeightGridMap2D.h>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "dlo/core/weighted_cloud.h"
#include "dlo/formats/height_map_centroids.h"
#include "dlo/slam/slam_map.h"

namespace dlo {

/// A CHeightGridMap2D covering the x-y bounds of `world_points` plus `margin` metres, with cells
/// of `resolution` metres, each holding the mean height of the points in it as
/// CHeightGridMap2D::insertIndividualPoint() would: a weighted point (centroid of n points)
/// counts n times in the weight w, in the sum u and (as n points at the centroid) in the sum of
/// squares v, so h = u / w and later insertions continue the same running mean.
/// An empty cloud gives a single-cell map with no observed cell.
mrpt::maps::CHeightGridMap2D toHeightGridMap(const WeightedCloud& world_points, double resolution,
                                             double margin);

/// toHeightGridMap() over clouds given one at a time (e.g. keyframe by keyframe with
/// forEachWorldCloud()), so that the points never need to be in memory together: first
/// extend() with every cloud (bounds), then add() every cloud (sums), then grid().
class HeightGridAccumulator {
 public:
  HeightGridAccumulator(double resolution, double margin);
  /// First pass: widens the bounds to cover `world_points`.
  void extend(const WeightedCloud& world_points);
  /// Second pass: adds the points to the cells (the grid is sized by the first call).
  void add(const WeightedCloud& world_points);
  /// The finished grid (cells with mean, sums and variance as toHeightGridMap() describes).
  mrpt::maps::CHeightGridMap2D grid();
  /// Where the points of each of grid()'s cells lie in it, weighted as the heights are
  /// (`heightmap_centroids.bin`).
  HeightMapCentroids centroids();

 private:
  void allocate();
  double resolution_, margin_;
  double x_min_ = std::numeric_limits<double>::infinity(), y_min_ = x_min_;
  double x_max_ = -x_min_, y_max_ = -x_min_;
  std::optional<mrpt::maps::CHeightGridMap2D> grid_;
  // Sums in double: a cell can gather thousands of points, float sums of z^2 would drift.
  std::vector<double> sum_, sum_sq_;
  /// Per cell, the sums of where its points fell along its columns and rows (fractions of it,
  /// weighted): float is plenty for a place written in 256ths of the cell.
  std::vector<float> sum_u_, sum_v_;
  std::vector<std::uint64_t> count_;
};

/// Serialises `grid` (usually HeightGridAccumulator::grid() over forEachWorldCloud()) with
/// mrpt::io::CFileGZOutputStream and archiveFrom(...) << grid, atomically; read it back with
/// CFileGZInputStream and archiveFrom(...) >> grid.
/// \throws OutputError naming `path`.
void exportHeightGridMap(const mrpt::maps::CHeightGridMap2D& grid, const std::string& path);

/// Writes `object` MRPT-serialised in a gzip stream (what MRPT's tools read for .gridmap,
/// heightmap and .simplemap files), atomically, at zlib's `level` (0: stored, not deflated; 1:
/// fastest; 9: smallest). \throws OutputError naming `path`.
void exportSerializedGz(const mrpt::serialization::CSerializable& object, const std::string& path,
                        int level = 1);

}  // namespace dlo
