/// \file local_height_map.h
/// \brief LocalHeightMap: a world-fixed height map of the last few registered scans, the
/// reference that sparse sensors need.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include <Eigen/Geometry>

#include "dlo/core/grid_geometry.h"
#include "dlo/core/point_cloud.h"

namespace dlo {

/// Counts and height sums of the points of the last `max_scans` scans, in cells fixed in the
/// odometry frame (axis-aligned, `resolution` wide), updated scan by scan.
///
/// Why: a single sparse scan (VLP-16, HDL-32) measures the ground only along its laser rings,
/// and the rings travel with the sensor. Registered against such a scan, the edges between
/// ring cells and hole-filled cells match best at zero motion: simulated VLP-16 drives lost a
/// quarter of their forward motion frame to frame. The rings of many scans (15 in dlo-slam),
/// each placed at its registered pose, cover the ground densely, so the reference holds no
/// sensor-locked pattern.
///
/// Storage is a square of `span` x `span` cells addressed modulo `span` (a torus): inserting
/// and evicting cost the points of one scan, and nothing moves when the vehicle does. Scans are
/// evicted by age and by distance, so that no two live cells alias (see insert()).
class LocalHeightMap {
 public:
  /// \param resolution metres per cell, the finest grid level's.
  /// \param window_cols, window_rows the grid that insert() crops scans to and that
  ///        fillWindow() extracts (the registration grid).
  /// \param max_scans scans kept; the oldest is removed when a new one comes.
  LocalHeightMap(double resolution, int window_cols, int window_rows, int max_scans);

  /// Adds a scan: `points` in the vehicle frame, within the registration window around the
  /// vehicle and [min_z, max_z] (vehicle frame, as the scan's own grid), placed by `pose`
  /// (vehicle in the odometry frame). Removes the oldest scan beyond max_scans and any scan
  /// farther from `pose` than evictionDistance().
  void insert(const PointCloud& points, const Eigen::Isometry3d& pose, double min_z, double max_z);

  /// Forgets every scan.
  void clear();

  /// The origin of the window grid centred near `position` (odometry frame): a translation
  /// chosen so that the cells of GridGeometry::centred(window_cols, window_rows, resolution)
  /// coincide with this map's cells.
  Eigen::Isometry3d windowPose(const Eigen::Vector3d& position) const;

  /// Writes the counts and height sums of the window at `window_pose` (from windowPose()) into
  /// `count` and `sum` (window_cols x window_rows, row-major, zeroed by the caller): the input
  /// of HeightGrid::accumulateCells().
  void fillWindow(const Eigen::Isometry3d& window_pose, std::uint32_t* count, float* sum) const;

  size_t scans() const { return scans_.size(); }
  /// Metres: a scan whose pose is farther than this from the newest is evicted.
  double evictionDistance() const;

 private:
  /// One scan's contribution to a cell.
  struct Delta {
    std::uint32_t cell;
    std::uint32_t count;
    float sum;
  };
  struct Scan {
    Eigen::Vector2d position;
    std::vector<Delta> deltas;
  };
  /// A point of the scan being inserted: its cell and height.
  struct CellPoint {
    std::uint32_t cell;
    float z;
  };

  std::uint32_t cellIndex(std::int64_t gx, std::int64_t gy) const;
  void evict(const Scan& scan);

  double resolution_;
  int window_cols_;
  int window_rows_;
  int max_scans_;
  int span_;  ///< cells per side of the torus
  std::vector<std::uint32_t> count_;
  std::vector<float> sum_;
  /// Per cell: 1 + index of its entry in the deltas of the scan being inserted, 0 if untouched.
  std::vector<std::uint32_t> slot_;
  std::deque<Scan> scans_;
  std::vector<CellPoint> cell_points_;  ///< insert()'s buffer, kept across scans
  std::vector<Delta> spare_;            ///< the last evicted scan's deltas, reused by insert()
};

}  // namespace dlo
