/// \file occupancy_grid_export.h
/// \brief A 2D occupancy grid made from the 2.5D map, for MRPT's localisation and navigation
/// (mrpt::maps::COccupancyGridMap2D) and for ROS's map_server (PNG + YAML).
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <string>
#include <vector>

#include "dlo/core/weighted_cloud.h"

namespace dlo {

/// How the occupancy grid is made from the map's points.
struct OccupancyGridOptions {
  double resolution = 0.2;  ///< metres per cell
  /// A cell is an obstacle where a point rises more than this above the local ground (metres):
  /// kerbs stay free, a car's bumper or a wall's base does not. The local ground is the lowest
  /// point around, so on a slope it lies lower by up to the grade times ground_radius: 0.4 m
  /// keeps a kerb on a 20 % grade free.
  double obstacle_height = 0.4;
  /// Points higher than this above the local ground are ignored (metres): tree canopies and
  /// overhangs a vehicle passes under.
  double max_height = 2.5;
  /// The local ground of a cell is the lowest point within this distance (metres): the ground
  /// beside a wall, whose own cells hold no ground point.
  double ground_radius = 1.0;
  double margin = 2.0;  ///< metres added around the points' x-y bounds
};

/// Builds the occupancy grid from world-frame clouds fed one at a time (a long run's map is not
/// held in memory): extend() with every cloud, then ground() with every cloud, then classify()
/// with every cloud, then grid().
///
/// A cell is occupied (free probability 0) where any point lies between obstacle_height and
/// max_height above its local ground, free (1) where points were seen and all of them are
/// ground, unknown (0.5) where none was.
class OccupancyGridAccumulator {
 public:
  explicit OccupancyGridAccumulator(const OccupancyGridOptions& options);

  /// Pass 1: grows the x-y bounds.
  void extend(const WeightedCloud& world_points);
  /// Pass 2: the lowest point of every cell.
  void ground(const WeightedCloud& world_points);
  /// Pass 3: counts, per cell, points on the ground and points of obstacles.
  void classify(const WeightedCloud& world_points);
  /// After ground() with every cloud: how far `z` lies above the local ground at (x, y), as
  /// classify() judges it; NaN outside the grid or where no ground was seen within
  /// ground_radius.
  float heightAboveGround(float x, float y, float z);
  /// The grid (empty, 1 x 1 unknown cell, when no point was seen).
  mrpt::maps::COccupancyGridMap2D grid() const;

 private:
  void allocate();
  bool cellOf(float x, float y, int& cx, int& cy) const;
  void computeLocalGround();

  OccupancyGridOptions options_;
  double xmin_, xmax_, ymin_, ymax_;
  bool bounded_ = false;
  int cols_ = 0, rows_ = 0;
  std::vector<float> lowest_;        ///< per cell; +inf where no point
  std::vector<float> local_ground_;  ///< lowest within ground_radius, after pass 2
  std::vector<std::uint8_t> seen_, occupied_;
};

/// Writes `grid` as `stem`.gridmap (MRPT's serialised COccupancyGridMap2D, gzip-compressed, as
/// pf-localization and the navigation apps read it), `stem`.png (black occupied, white free,
/// grey unknown; the top row is the largest y) and `stem`.yaml (ROS map_server: image,
/// resolution, origin of the lower-left pixel, thresholds). Each file atomically.
/// \return the paths written. \throws OutputError naming the file that failed.
std::vector<std::string> exportOccupancyGrid(const mrpt::maps::COccupancyGridMap2D& grid,
                                             const std::string& stem);

}  // namespace dlo
