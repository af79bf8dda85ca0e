/// \file height_grid.h
/// \brief HeightGrid: the 2.5D "height image" of a scan, mean height per cell.
#pragma once

#include <cstdint>
#include <functional>
#include <opencv2/core/mat.hpp>
#include <vector>

#include "dlo/core/deskew.h"
#include "dlo/core/grid_geometry.h"
#include "dlo/core/point_cloud.h"
#include "dlo/core/weighted_cloud.h"

namespace dlo {

/// Parameters of the finest grid level (INI section [grid]).
struct HeightGridParams {
  int cols = 400;            ///< cells along x (paper: 400)
  int rows = 400;            ///< cells along y (paper: 400)
  double resolution = 0.10;  ///< metres per cell at the finest level (paper: 0.10)
  int min_points = 3;        ///< a cell needs at least this many points to be valid (paper: 3)
  double min_z = -10.0;      ///< points below this height (m, grid frame) are ignored
  double max_z = 10.0;       ///< points above this height (m, grid frame) are ignored
  int levels = 4;            ///< pyramid levels; level k has cells 2^k times larger
};

/// A coarse level laid out for the "pull" of hole filling (HeightGrid::fillHolesFrom and
/// pulledRow): support (0 or 1) and support-weighted height per cell, with a one-cell border
/// of zeros, so that the interpolation needs neither branches nor bounds checks: height =
/// sum(w*s*h) / sum(w*s) over the four surrounding coarse cells.
struct PullSource {
  GridGeometry geometry;       ///< of the coarse level, without the border
  int cols = 0;                ///< padded columns: geometry.cols + 2
  std::vector<float> support;  ///< (geometry.rows + 2) x cols, row-major
  std::vector<float> height;   ///< support * mean height, same layout
};

/// One level of mean heights. Built in a single pass over the points, accumulating a count and a
/// sum of heights per cell in flat arrays; coarser levels pool 2x2 blocks of those sums, so the
/// mean of a coarse cell is exactly the mean of the points falling in it.
class HeightGrid {
 public:
  HeightGrid() = default;

  /// Rasterises `points` (grid frame) into `geometry`. Points outside the grid, outside
  /// [min_z, max_z] or non-finite are skipped.
  static HeightGrid fromPoints(const PointCloud& points, const GridGeometry& geometry,
                               int min_points, double min_z, double max_z);

  /// A grid from per-cell mean heights and point counts, row-major (row = y index). Used to
  /// import grids built elsewhere, e.g. mrpt::maps::CHeightGridMap2D. A cell is valid when
  /// count >= min_points and its height is finite.
  static HeightGrid fromCells(const GridGeometry& geometry, const std::vector<float>& mean_heights,
                              const std::vector<std::uint32_t>& counts, int min_points);

  /// In-place form of fromPoints(): reuses this grid's memory, for streaming.
  void rasterise(const PointCloud& points, const GridGeometry& geometry, int min_points,
                 double min_z, double max_z);
  /// Rasterises a sweep deskewed on the fly: point i counts at motion.apply(i, points[i]), the
  /// same as rasterising deskew(points, motion) without writing and re-reading that copy.
  /// `motion` is ignored unless it fits the cloud (SweepMotion::fits). With `coarser` (not this
  /// grid), that grid also becomes this one's coarser() level, exactly as
  /// coarser->poolFrom(*this) would make it, pooled in the same pass over the cells.
  void rasterise(const PointCloud& points, const SweepMotion& motion, const GridGeometry& geometry,
                 int min_points, double min_z, double max_z, HeightGrid* coarser = nullptr);

  /// Rasterises weighted points (voxel centroids with counts) seen from `pose`: each point is
  /// mapped by pose * p into the grid frame and counts n times. Used to rebuild keyframe grids
  /// and to fuse several keyframes into a local map.
  void rasterise(const WeightedCloud& points, const Eigen::Isometry3d& pose,
                 const GridGeometry& geometry, int min_points, double min_z, double max_z);
  /// Rasterises several posed clouds into one grid (their counts and sums add up). `coarser` as
  /// for sweeps.
  void rasterise(const std::vector<PosedCloud>& parts, const GridGeometry& geometry, int min_points,
                 double min_z, double max_z, HeightGrid* coarser = nullptr);

  /// With `keep`, the next rasterisations of sweeps and posed clouds also sum where in its cell
  /// each point fell (centroidSums()): one more array to clear and add into, so off by default.
  void keepCentroidSums(bool keep) { keep_centroids_ = keep; }
  /// Per cell (row-major, then a few discard cells), two sums over its points, weighted like
  /// count(): at 2 i, where along the cell's columns each fell, as a fraction of the cell in
  /// [0, 1); at 2 i + 1, the same along its rows. The centroid of cell (row, col) is
  /// x = x_min + resolution * (col + sums[2 i] / count), y = y_min + resolution * (row +
  /// sums[2 i + 1] / count). Empty unless the last rasterisation kept them
  /// (keepCentroidSums()).
  const std::vector<float>& centroidSums() const { return sum_uv_; }

  /// Per-cell point counts and height sums, row-major, for accumulateCells().
  using CellFiller = std::function<void(std::uint32_t* count, float* sum)>;
  /// Rebuilds this grid from the counts and height sums that `fill` writes into zeroed arrays
  /// of `geometry`'s size: cells accumulated elsewhere, e.g. a LocalHeightMap window.
  /// `coarser` as for rasterise().
  void accumulateCells(const GridGeometry& geometry, int min_points, const CellFiller& fill,
                       HeightGrid* coarser = nullptr);

  /// The next coarser level (cells twice as large) from pooled sums and counts.
  HeightGrid coarser() const;
  /// In-place form of coarser(): this grid becomes finer.coarser(), reusing its memory.
  void poolFrom(const HeightGrid& finer);

  /// Fills cells without measurements from `coarser` (this grid's coarser() level, itself
  /// already filled; anything else throws std::invalid_argument),
  /// by bilinear interpolation of its supported cells: the "pull" half of push-pull hole
  /// filling. At 0.1 m an HDL-64 scan leaves most ground cells between rings empty, which would
  /// mask the gradient of nearly every wall and curb; filled cells give those edges a
  /// neighbourhood without inventing edges against "zero height". Measured cells are untouched
  /// and remain the only ones isValid().
  void fillHolesFrom(const HeightGrid& coarser);

  /// This grid (as the coarser level of another) laid out for pulledRow().
  void preparePull(PullSource& out) const;
  /// One row of heights as fillHolesFrom(coarser) would leave them, without filling the grid:
  /// height[c] is the cell's own height where hasSupport(), else the pulled estimate, and
  /// has[c] is 1 where the cell has a height, 0 where it would stay empty (height[c] is then
  /// meaningless), for every column c. Lets a scan that is only registered, never a reference,
  /// compute the gradients of its measured cells without filling its finest level. `source`
  /// comes from coarser.preparePull(), with isCoarserLevel(coarser) (unchecked), or is nullptr
  /// for no filling. `scratch` is working memory, reused across calls. With `first` and `end`,
  /// only columns [first, end) are computed and written (end < 0: to the last column).
  void pulledRow(int row, const PullSource* source, float* height, float* has,
                 std::vector<float>& scratch, int first = 0, int end = -1) const;
  /// True when `coarser` has this grid's coarser() geometry (what fillHolesFrom() requires).
  bool isCoarserLevel(const HeightGrid& coarser) const;

  const GridGeometry& geometry() const { return geometry_; }
  int cols() const { return geometry_.cols; }
  int rows() const { return geometry_.rows; }
  double resolution() const { return geometry_.resolution; }

  /// The cell holds at least min_points measured points.
  bool isValid(int row, int col) const { return valid_[index(row, col)] != 0; }
  /// The cell has a height: measured (isValid) or filled by fillHolesFrom().
  bool hasSupport(int row, int col) const { return support_[index(row, col)] != 0; }
  /// Height of the cell, metres: the mean of its points where isValid(), the filled estimate
  /// where only hasSupport(); meaningless elsewhere.
  float height(int row, int col) const { return height_[index(row, col)]; }
  std::uint32_t count(int row, int col) const { return count_[index(row, col)]; }
  int validCellCount() const { return valid_cells_; }
  int minPoints() const { return min_points_; }

  /// Heights as an image (CV_32F, rows x cols, row 0 = y_min); invalid cells hold NaN.
  cv::Mat heightImage() const;

  /// Reads every cache line of the grid's arrays (counts, sums, heights, flags), so that the next
  /// build finds them in the cache after other work has evicted them. Changes nothing.
  void warmCaches() const;

  /// Raw row-major arrays, for fast loops.
  const std::vector<float>& heights() const { return height_; }
  const std::vector<std::uint8_t>& validMask() const { return valid_; }
  const std::vector<std::uint8_t>& supportMask() const { return support_; }
  /// Points (or weights) per cell, row-major, as count().
  const std::vector<std::uint32_t>& counts() const { return count_; }

 private:
  int index(int row, int col) const { return row * geometry_.cols + col; }
  /// Zeroes count_ and sum_z_ for geometry_: one entry per cell plus a few last "discard"
  /// cells that rasterisation sends rejected points to; sum_uv_ too with `centroids`,
  /// else empties them.
  void clearSums(bool centroids = false);
  /// Makes this grid the empty coarser() level of `finer` (geometry, minimum points, zeroed
  /// sums), ready for finer's cells to be pooled into it.
  void startPooling(const HeightGrid& finer);
  /// Heights and valid flags from the counts and sums; with `coarser`, pools it from this grid
  /// in the same pass (then finalises it).
  void finalise(HeightGrid* coarser);

  GridGeometry geometry_;
  int min_points_ = 3;
  int valid_cells_ = 0;
  std::vector<std::uint32_t> count_;
  std::vector<float> sum_z_;
  bool keep_centroids_ = false;
  std::vector<float> sum_uv_;
  std::vector<float> height_;
  std::vector<std::uint8_t> valid_;
  std::vector<std::uint8_t> support_;
};

}  // namespace dlo
